"""The results folder of a fleet run and its Parquet tables.

    OUT/run.json                  settings, versions, counts and timing of the last run
    OUT/logs.parquet              one row per log and arithmetic, sorted by (log_id, arith)
    OUT/bands.parquet             residual moments per log, arithmetic, quantity, speed band
    OUT/steps/arith=A/log_id=ID/part-0.parquet   per-step outputs (fleet run --steps)
    OUT/_journal/                 rows of a run in progress; folded into the tables at its end

Rows reach the journal in parts while the run goes on, so a run that is
stopped keeps what it finished; the next run folds the journal in first.
Every table is written to a temporary name and renamed (no reader ever
sees half a file).
"""
import glob
import json
import os
import shutil
import time
import uuid

LOGS, BANDS, STEPS, JOURNAL, RUN = "logs.parquet", "bands.parquet", "steps", "_journal", "run.json"
KEY = ("log_id", "arith")
BAND_KEY = ("log_id", "arith", "quantity", "band")


def _pa():
    import pyarrow as pa
    import pyarrow.parquet as pq
    return pa, pq


def write_table(path, table):
    _, pq = _pa()
    tmp = f"{path}.tmp-{uuid.uuid4().hex[:8]}"
    pq.write_table(table, tmp, compression="zstd")
    os.replace(tmp, path)


def read_table(path):
    _, pq = _pa()
    return pq.read_table(path) if os.path.exists(path) else None


def rows_table(rows, schema=None):
    """A list of dicts as a table; column order: schema's, then the rest in
    first-seen order; types from schema where given, else inferred."""
    pa, _ = _pa()
    names = list(schema.names) if schema is not None else []
    seen = set(names)
    for r in rows:
        for k in r:
            if k not in seen:
                names.append(k)
                seen.add(k)
    arrays, fields = [], []
    for n in names:
        vals = [r.get(n) for r in rows]
        if schema is not None and n in schema.names:
            t = schema.field(n).type
            arrays.append(pa.array(vals, type=t))
        else:
            arrays.append(pa.array(vals))
        fields.append(pa.field(n, arrays[-1].type))
    return pa.Table.from_arrays(arrays, schema=pa.schema(fields))


def concat(tables):
    """Tables with possibly different columns -> one (missing columns null,
    types unified: a column that is null-only in one table takes the other's)."""
    pa, _ = _pa()
    tables = [t for t in tables if t is not None and t.num_rows > 0]
    if not tables:
        return None
    return pa.concat_tables(tables, promote_options="permissive")


def sort(table, keys):
    return table.sort_by([(k, "ascending") for k in keys])


class Results:
    def __init__(self, out):
        self.out = out
        os.makedirs(out, exist_ok=True)
        self.journal = os.path.join(out, JOURNAL)

    def path(self, name):
        return os.path.join(self.out, name)

    def steps_dir(self):
        return os.path.join(self.out, STEPS)

    # ------------------------------------------------------------------
    def _journal_tables(self, kind):
        _, pq = _pa()
        return [pq.read_table(p) for p in sorted(glob.glob(os.path.join(self.journal, f"{kind}-*.parquet")))]

    def load(self):
        """(logs, bands) tables of earlier runs, journal included (None when empty)."""
        logs = concat([read_table(self.path(LOGS))] + self._journal_tables("logs"))
        bands = concat([read_table(self.path(BANDS))] + self._journal_tables("bands"))
        if logs is not None:
            logs = _last_per_key(logs, KEY)
        return logs, bands

    def previous(self):
        """{log_id: {arith: (status, input_hash, grip_version, replay_id)}} of the stored rows."""
        logs, _ = self.load()
        prev = {}
        if logs is None:
            return prev
        d = logs.select(["log_id", "arith", "status", "input_hash", "grip_version", "replay_id"]).to_pydict()
        for i in range(len(d["log_id"])):
            prev.setdefault(d["log_id"][i], {})[d["arith"][i]] = (d["status"][i], d["input_hash"][i],
                                                                   d["grip_version"][i], d["replay_id"][i])
        return prev

    def append_journal(self, log_rows, band_rows, schema=None):
        if not log_rows:
            return
        os.makedirs(self.journal, exist_ok=True)
        tag = f"{time.time_ns():020d}-{uuid.uuid4().hex[:8]}"     # sorts in write order
        write_table(os.path.join(self.journal, f"logs-{tag}.parquet"), rows_table(log_rows, schema))
        if band_rows:
            write_table(os.path.join(self.journal, f"bands-{tag}.parquet"), rows_table(band_rows))

    def compact(self, keep_ids, log_schema=None):
        """Fold the journal into logs.parquet / bands.parquet: the newest
        row per (log_id, arith), only logs in keep_ids, sorted. Per-step
        partitions of logs no longer in the set are removed."""
        import pyarrow.compute as pc
        pa, _ = _pa()
        logs, bands = self.load()
        keep = pa.array(sorted(keep_ids), pa.string())
        if logs is not None:
            logs = sort(logs.filter(pc.is_in(logs["log_id"], value_set=keep)), KEY)
            if log_schema is not None:
                logs = _order(logs, log_schema)
            write_table(self.path(LOGS), logs)
            if bands is not None:
                # the bands of the rows kept (a recomputed log's older bands go)
                ok = set(zip(logs["log_id"].to_pylist(), logs["arith"].to_pylist(),
                             logs["input_hash"].to_pylist(), logs["replay_id"].to_pylist()))
                d = bands.select(["log_id", "arith", "input_hash", "replay_id"]).to_pydict()
                mask = [(a, b, c, e) in ok for a, b, c, e in zip(d["log_id"], d["arith"], d["input_hash"],
                                                                 d["replay_id"])]
                bands = sort(bands.filter(pa.array(mask, pa.bool_())), BAND_KEY)
                write_table(self.path(BANDS), _dedup(bands, BAND_KEY))
        if os.path.isdir(self.journal):
            shutil.rmtree(self.journal)
        sd = self.steps_dir()
        if os.path.isdir(sd):
            keep_set = set(keep_ids)
            for p in glob.glob(os.path.join(sd, "arith=*", "log_id=*")):
                if p.split("log_id=", 1)[1] not in keep_set:
                    shutil.rmtree(p, ignore_errors=True)
        return logs

    def write_run(self, info):
        tmp = self.path(RUN) + ".tmp"
        with open(tmp, "w") as f:
            json.dump(info, f, indent=1, sort_keys=True)
        os.replace(tmp, self.path(RUN))


def _last_per_key(table, key):
    """The last row of each key (later journal parts win over older tables)."""
    pa, _ = _pa()
    d = table.select(list(key)).to_pydict()
    last = {}
    for i, k in enumerate(zip(*(d[c] for c in key))):
        last[k] = i
    return table.take(pa.array(sorted(last.values()), pa.int64()))


def _dedup(table, key):
    return _last_per_key(table, key) if table.num_rows else table


def _order(table, schema):
    """Columns in schema order first (the fixed part of the logs table)."""
    names = [n for n in schema.names if n in table.column_names]
    names += [n for n in table.column_names if n not in names]
    return table.select(names)


def write_steps(steps_dir, log_id, arith, table):
    """One log's per-step table, atomically (a retried task rewrites it whole)."""
    d = os.path.join(steps_dir, f"arith={arith}", f"log_id={log_id}")
    os.makedirs(d, exist_ok=True)
    write_table(os.path.join(d, "part-0.parquet"), table)
    return d
