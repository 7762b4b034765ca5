"""The Python package's C declarations (python/voussoir/_lib.py) against the library's headers:
writes a C file that includes the headers, redeclares every function of the cdef (a prototype
that differs from the header's is a compile error) and asserts, for every struct of the cdef,
the header's size and each field's offset and size as cffi lays them out (vs_case, held opaque,
must fit in the cdef's buffer), and the status codes and enum values the package uses. Then
compiles it with -Werror.
usage: python3 python_cdef_check.py CC OUT_DIR -IDIR...   (voussoir._lib importable)"""
import os
import subprocess
import sys

from voussoir import _lib
from voussoir import inprocess, study

cc, out, incs = sys.argv[1], sys.argv[2], sys.argv[3:]
ffi = _lib.ffi
lines = ["#include <signal.h>", "#include <stddef.h>", '#include "voussoir/voussoir.h"',
         '#include "voussoir/hinges.h"', '#include "voussoir/model.h"',
         '#include "voussoir/montecarlo.h"', '#include "voussoir/support.h"', "",
         "/* the cdef's functions: each must be the header's prototype */",
         _lib.CDEF_FUNCTIONS, "/* the cdef's structs: the header's layout */"]
n = 0


def check(expr, what):
    global n
    n += 1
    lines.append(f'_Static_assert({expr}, "{what}");')


for name in ("vs_error", "vs_energy", "vs_run_sample", "vs_run_event", "vs_hinge", "vs_slip",
             "vs_limit_record", "vs_collapse_record", "vs_mc_sample", "vs_run_load_result"):
    t = ffi.typeof(name)
    check(f"sizeof({name}) == {ffi.sizeof(t)}", f"{name}: size")
    for field, f in t.fields:
        check(f"offsetof({name}, {field}) == {f.offset}", f"{name}.{field}: offset")
        check(f"sizeof((({name} *)0)->{field}) == {ffi.sizeof(f.type)}", f"{name}.{field}: size")
check(f"sizeof(vs_case) <= {ffi.sizeof('vs_case')}", "vs_case: larger than the cdef's buffer")
check(f"_Alignof(vs_case) <= {ffi.alignof('vs_case')}", "vs_case: alignment")
for name, value in _lib.STATUS.items():
    check(f"{name} == {value}", f"{name}")
for i, kind in enumerate(inprocess._EVENTS):
    check(f"VS_EVENT_{kind.upper()} == {i}", f"event {kind}")
for i, phase in enumerate(inprocess._PHASES):
    check(f"VS_PHASE_{phase.upper()} == {i}", f"phase {phase}")
for i, status in enumerate(("COLLAPSE", "NO_COLLAPSE", "FAILED")):
    check(f"VS_MC_{status} == {i}", f"montecarlo status {status}")
check(f"sizeof VS_MC_TABLE_COLUMNS == {len(','.join(study.MC_COLUMNS)) + 1}",
      "montecarlo columns")
lines.append("static const char columns[] = VS_MC_TABLE_COLUMNS;")
lines.append("int main(void) { return columns[0] == 's' ? 0 : 1; }")

os.makedirs(out, exist_ok=True)
src = os.path.join(out, "cdef_check.c")
with open(src, "w") as f:
    f.write("\n".join(lines) + "\n")
cmd = [cc, "-std=c17", "-Wall", "-Wextra", "-Werror", "-c", src, "-o",
       os.path.join(out, "cdef_check.o")] + incs
p = subprocess.run(cmd, capture_output=True, text=True)
if p.returncode != 0:
    print(p.stderr)
    print("FAIL: the cdef of python/voussoir/_lib.py differs from the headers (" + src + ")")
    sys.exit(1)
print(f"cdef: {len(_lib.CDEF_FUNCTIONS.strip().splitlines())} lines of functions, {n} layout "
      "checks: ok")
