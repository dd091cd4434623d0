#!/usr/bin/env python3
"""filter.py DEVIATIONS FINDINGS - sorts static-analysis findings into
covered (a whole-rule deviation of DEVIATIONS, or a "grip-deviation: ID" tag
on the finding's line or the line above) and uncovered. FINDINGS lines:
  path:line:id:message      (id: misra-c2012-x.y, a cppcheck id or a
                             clang-tidy check name)
Prints a summary line "# N findings: G global, T tagged, U uncovered", the
per-id counts and every uncovered finding; exit 1 if any is uncovered.
Also writes the set of tags used to FINDINGS.tags (for the stale-tag check).
"""
import os
import re
import sys


def norm(fid):
    m = re.match(r'misra-c2012-(\d+\.\d+)$', fid)
    return 'MISRA-' + m.group(1) if m else fid


def main():
    devfile, findfile = sys.argv[1], sys.argv[2]
    dev = {}
    for line in open(devfile):
        s = line.split('#', 1)[0].split()
        if s:
            dev[s[0]] = s[1:]
    cache = {}
    counts = {}
    glob_n = tag_n = 0
    unc = []
    used = set()
    seen = set()
    for line in open(findfile):
        parts = line.rstrip('\n').split(':', 3)
        if len(parts) < 4 or not parts[1].isdigit():
            continue
        path, ln, fid, msg = parts[0], int(parts[1]), norm(parts[2]), parts[3]
        path = os.path.relpath(path) if os.path.isabs(path) else path
        key = (path, ln, fid)
        if key in seen:
            continue
        seen.add(key)
        counts[fid] = counts.get(fid, 0) + 1
        if fid in dev and (not dev[fid] or any(path.startswith(p) for p in dev[fid])):
            glob_n += 1
            continue
        if path not in cache:
            try:
                cache[path] = open(path, errors='replace').read().split('\n')
            except OSError:
                cache[path] = []
        src = cache[path]
        near = ' '.join(src[max(0, ln - 2):ln])
        tags = re.findall(r'grip-deviation:\s*([A-Za-z0-9_.\-]+)', near)
        if fid in tags:
            tag_n += 1
            used.add('%s:%s' % (path, fid))
            continue
        unc.append('%s:%d: %s %s' % (path, ln, fid, msg))
    with open(findfile + '.tags', 'w') as f:
        f.write('\n'.join(sorted(used)) + '\n')
    print('# %d findings: %d under whole-rule deviations, %d tagged in the code, %d uncovered' % (
        len(seen), glob_n, tag_n, len(unc)))
    if counts:
        print('# by id: ' + ', '.join('%s %d' % (k, counts[k]) for k in sorted(counts)))
    for u in unc:
        print('# UNCOVERED ' + u)
    return 1 if unc else 0


if __name__ == '__main__':
    sys.exit(main())
