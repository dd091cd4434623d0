#!/bin/sh
# Checks of one firmware build: code/data size, worst-case stack per public
# function, and the floating-point rule:
#   fixed build: no floating-point helper or FPU instruction at all;
#   float build: single precision only (no double-precision helper).
# Usage: check.sh BUILD_DIR float|fixed. Prints TAP lines; exits 1 on failure.
set -u
dir=$1
arith=$2
lib=$dir/libgrip.a
elf=$dir/grip-example.elf
n=0
fail=0
tap() { n=$((n + 1)); if [ "$1" = ok ]; then echo "ok $n - $2"; else echo "not ok $n - $2"; fail=1; fi; }

echo "# firmware $dir ($arith)"
arm-none-eabi-size -t "$lib" | tail -1 | awk '{printf "# libgrip.a total: text %d B, data %d B, bss %d B\n", $1, $2, $3}'
arm-none-eabi-size "$elf" | tail -1 | awk '{printf "# example image: text %d B, data %d B, bss %d B\n", $1, $2, $3}'

# Soft-float helpers of libgcc (ARM EABI names and generic GCC names).
SF_SINGLE='__aeabi_f[a-z0-9]*|__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord)sf[23]|__(fix|fixuns)sf[sd]i|__float(un)?[sd]isf|__extendsfdf2|__truncdfsf2'
SF_DOUBLE='__aeabi_d[a-z0-9]*|__(add|sub|mul|div|neg|cmp|eq|ne|lt|le|gt|ge|unord)df[23]|__(fix|fixuns)df[sd]i|__float(un)?[sd]idf'
undef=$(arm-none-eabi-nm -u "$lib" | awk '{print $2}' | sort -u)
linked=$(arm-none-eabi-nm "$elf" | awk '{print $3}' | sort -u)
if [ "$arith" = fixed ]; then
    bad=$(printf '%s\n%s\n' "$undef" "$linked" | grep -E "^($SF_SINGLE|$SF_DOUBLE)$" | sort -u)
    [ -z "$bad" ] && tap ok "fixed build references no soft-float helper" \
                  || { echo "# soft-float helpers: $bad"; tap fail "fixed build references no soft-float helper"; }
    # No libm either: the fixed library must not call sinf, sqrt, ...
    badm=$(printf '%s\n' "$undef" | grep -E '^(sin|cos|tan|atan|atan2|exp|log|sqrt|pow|fabs|floor|ceil)f?$' || true)
    [ -z "$badm" ] && tap ok "fixed build calls no libm function" \
                   || { echo "# libm calls: $badm"; tap fail "fixed build calls no libm function"; }
    # No VFP instruction in the library code (a Cortex-M0+ has none).
    vfp=$(arm-none-eabi-objdump -d "$lib" | grep -cE '\s(vldr|vstr|vmov|vadd|vsub|vmul|vdiv|vcvt|vsqrt|vcmp)' || true)
    [ "$vfp" = 0 ] && tap ok "fixed build contains no FPU instruction" \
                   || tap fail "fixed build contains no FPU instruction ($vfp found)"
else
    bad=$(printf '%s\n' "$undef" | grep -E "^($SF_DOUBLE)$" | sort -u)
    [ -z "$bad" ] && tap ok "float build uses single precision only (no double helper)" \
                  || { echo "# double helpers: $bad"; tap fail "float build uses single precision only (no double helper)"; }
fi
# The status is the stack tool's, not that of the sed after it (a pipe
# returns its last command's status: an over-budget function passed before).
stack_out=$(PYTHONPATH=tools .venv/bin/python -m grip_tools stack "$dir/lib" --budget 1024)
stack_rc=$?
printf '%s\n' "$stack_out" | sed 's/^/# /'
if [ "$stack_rc" = 0 ]; then
    tap ok "worst-case stack of every public function within 1024 B"
else
    tap fail "worst-case stack of every public function within 1024 B"
fi
echo "1..$n"
exit $fail
