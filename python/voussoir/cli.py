"""Run the voussoir program and return its results as data."""
import csv
import json
import os
import shutil
import subprocess


def _exe(program):
    exe = program or os.environ.get("VOUSSOIR") or shutil.which("voussoir")
    if exe is None:
        raise FileNotFoundError("voussoir program not found (set VOUSSOIR or pass program=)")
    return exe


def _sets(sets):
    args = []
    for k, v in (sets or {}).items():
        args += ["--set", f"{k}={v}"]
    return args


def run(case, record=None, sets=None, first_limit=False, program=None):
    """Run a case; returns the program's JSON summary as a dict (with 'record' = the record's
    path, or None). sets: {'joints.kn_N_mm3': 48, ...}. Raises CalledProcessError on bad
    input (exit 2); a failed run (exit 1) still returns its summary with status 'failed'."""
    args = [_exe(program), "run", str(case), "--json", "-q"] + _sets(sets)
    if first_limit:
        args.append("--first-limit")
    args += ["-o", str(record)] if record else ["--no-record"]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode not in (0, 1) or not p.stdout.strip():
        raise subprocess.CalledProcessError(p.returncode, args, p.stdout, p.stderr)
    out = json.loads(p.stdout)
    out["record"] = str(record) if record else None
    return out


def read_table(path):
    """A sweep's summary.csv as a list of dicts (numbers as floats where they parse)."""
    def num(x):
        try:
            return float(x)
        except ValueError:
            return x
    with open(path, newline="") as f:
        return [{k: num(v) for k, v in r.items()} for r in csv.DictReader(f)]


def sweep(case, out_dir, axes, sets=None, first_limit=False, jobs=None, program=None):
    """Run a sweep; axes: {'support.alpha_deg': '0:90:45', 'joints.kn_N_mm3': [1, 3]}. Returns
    the summary table (read_table of out_dir/summary.csv)."""
    args = [_exe(program), "sweep", str(case), "-q", "-o", str(out_dir)] + _sets(sets)
    for k, v in axes.items():
        v = ",".join(f"{x:g}" for x in v) if isinstance(v, (list, tuple)) else str(v)
        args += ["--vary", f"{k}={v}"]
    if first_limit:
        args.append("--first-limit")
    if jobs:
        args += ["-j", str(jobs)]
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode == 2:
        raise subprocess.CalledProcessError(p.returncode, args, p.stdout, p.stderr)
    return read_table(os.path.join(str(out_dir), "summary.csv"))
