"""shoal against DualSPHysics 5.4's CPU build on its 3D dam break, in one sitting (issue 34, item 2).

For each dp, runs the peer (``../shared/peers/dualsphysics-cpu/run.sh DP TMAX THREADS``, which prints one
JSON line) and shoal's ``benchmarks/bench_dambreak.py`` in float32 and float64, in the order

    peer, shoal float32, shoal float64, shoal float64, shoal float32, peer

(ABBA: a drift of the machine within the sitting cancels to first order), with the same number of
threads, and prints each run's particle-steps per second and the ratio shoal / peer per precision (the
sum of shoal's two runs over the sum of the peer's two). The 2-core machines differ by up to 2.5x from
one day to the next, so only a ratio measured in one sitting counts.

    python benchmarks/peer_sitting.py --dp 0.0085 0.0065 --json sitting.json
    python benchmarks/peer_sitting.py --peer PATH/run.sh --dp 0.0085 --steps 40 --tmax 0.02
    python benchmarks/peer_sitting.py --from-json sitting.json --table peer_cpu --date 2026-12-06 --commit abc1234

``--table NAME`` adds the sitting's rows (one per dp and code) to ``benchmarks/results/tables/NAME.json``, the
data file of the table the user guide shows (`benchmarks/readme_tables.py --write` puts it in the pages); the
sitting's JSON must be kept under ``benchmarks/results/`` (the rows name it as their source).

The peer's figure is its own "Steps per second" times its particle count over its whole run (set-up
included, about 1 % of a 0.02 s run at dp = 0.0085 m); shoal's is over ``--steps`` steps after
``--warmup`` untimed ones (compilation). Both start from rest.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "benchmarks" / "bench_dambreak.py"
PEER = ROOT.parent / "shared" / "peers" / "dualsphysics-cpu" / "run.sh"
RESULTS = ROOT / "benchmarks" / "results"
TABLE_ABOUT = ("shoal against DualSPHysics 5.4's CPU build (OpenMP) on DualSPHysics's 3D dam break (01_DamBreak), "
               "from rest, in one sitting on the project's 2-core machine, both codes with 2 threads "
               "(benchmarks/peer_sitting.py: peer, shoal float32, float64, float64, float32, peer). The ratio is "
               "shoal's two runs over the peer's two; only a ratio of one sitting counts.")


def fail(message, status=2):
    """One line on stderr, then exit (2: bad input)."""
    print(f"peer_sitting.py: error: {message}", file=sys.stderr)
    raise SystemExit(status)


def last_json(text, what):
    """The JSON object `text` ends with (one line, or the whole text indented)."""
    text = text.strip()
    for start in [text.rfind("\n{") + 1, text.find("{")]:
        try:
            obj = json.loads(text[start:])
        except ValueError:
            continue
        if isinstance(obj, dict):
            return obj
    fail(f"{what} printed no JSON object: {text[-300:]!r}", status=1)


def run_peer(peer, dp, tmax, threads):
    r = subprocess.run(["bash", str(peer), str(dp), str(tmax), str(threads)], capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"the peer failed (exit {r.returncode}): {' '.join((r.stderr or r.stdout).split())[-300:]}", 1)
    out = last_json(r.stdout, "the peer")
    return {"code": "DualSPHysics", "build": out.get("build"), "particles": out["particles"],
            "particle_steps_per_second": out["particle_steps_per_second"]}


def run_shoal(dp, precision, steps, warmup, threads):
    env = dict(os.environ, NUMBA_NUM_THREADS=str(threads))
    cmd = [sys.executable, str(BENCH), "--dp", str(dp), "--steps", str(steps), "--warmup", str(warmup),
           "--precision", precision, "--threads", str(threads)]
    r = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if r.returncode != 0:
        fail(f"bench_dambreak.py failed (exit {r.returncode}): {' '.join(r.stderr.split())[-300:]}", 1)
    out = last_json(r.stdout, "bench_dambreak.py")
    return {"code": "shoal", "precision": precision, "particles": out["particles"],
            "particle_steps_per_second": out["particle_steps_per_second"],
            "bytes_per_particle": out["bytes_per_particle"]}


def fmt(x):
    return f"{x:.2e}".replace("e+0", "e")


def table_rows(sitting, source, date, commit):
    """The rows one sitting adds to the table: per dp, the peer and shoal in each precision."""
    rows = []
    for dp in sorted({r["dp"] for r in sitting["runs"]}, reverse=True):
        runs = [r for r in sitting["runs"] if r["dp"] == dp]
        peer = [r for r in runs if r["code"] == "DualSPHysics"]
        peer_sum = sum(r["particle_steps_per_second"] for r in peer)
        what = [("DualSPHysics 5.4 CPU (%s build)" % peer[0]["build"], peer, "1")]
        for precision in ("float32", "float64"):
            mine = [r for r in runs if r.get("precision") == precision]
            ratio = sum(r["particle_steps_per_second"] for r in mine) / peer_sum
            what.append((f"shoal {precision} (commit {commit})", mine, f"**{ratio:.2f}**"))
        for name, rs, ratio in what:
            rates = [r["particle_steps_per_second"] for r in rs]
            rows.append({"measure": f"{name}, dp = {dp} m, {date}",
                         "values": [f"{rs[0]['particles']:,}", " / ".join(fmt(v) for v in rates), ratio],
                         "from": [source]})
    return rows


def add_to_table(name, sitting, source, date, commit):
    path = RESULTS / "tables" / f"{name}.json"
    data = json.loads(path.read_text()) if path.is_file() else {
        "about": TABLE_ABOUT, "measure_name": "run", "columns": ["particles", "rates", "ratio"],
        "column_names": ["particles", "particle-steps/s (runs in sitting order)", "shoal / DualSPHysics"],
        "rows": []}
    data["rows"] = table_rows(sitting, source, date, commit) + data["rows"]
    path.write_text(json.dumps(data, indent=1) + "\n")
    print(f"added {len(table_rows(sitting, source, date, commit))} rows to {path.relative_to(ROOT)}")


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--dp", type=float, nargs="+", default=[0.0085], help="particle spacings [m] (the peer has "
                   "inputs for 0.0085 and 0.0065)")
    p.add_argument("--steps", type=int, default=40, help="shoal's timed steps")
    p.add_argument("--warmup", type=int, default=3, help="shoal's untimed first steps")
    p.add_argument("--tmax", type=float, default=0.02, help="the peer's simulated time [s]")
    p.add_argument("--threads", type=int, default=os.cpu_count(), help="threads of both codes")
    p.add_argument("--peer", type=Path, default=PEER, help="the peer's run.sh")
    p.add_argument("--json", type=Path, help="write every figure to this file")
    p.add_argument("--from-json", type=Path, help="use a sitting's JSON written earlier instead of running one")
    p.add_argument("--table", help="add the sitting's rows to benchmarks/results/tables/TABLE.json")
    p.add_argument("--date", help="the sitting's date, for --table")
    p.add_argument("--commit", help="the commit shoal ran, for --table")
    a = p.parse_args(argv)
    if a.table and not (a.date and a.commit):
        fail("--table needs --date and --commit (they name the rows)")
    if a.from_json:
        if not a.from_json.is_file():
            fail(f"--from-json {a.from_json} is not a file")
        if not a.table:
            fail("--from-json is for --table: give --table NAME")
        source = a.from_json.resolve()
        if RESULTS not in source.parents:
            fail(f"--from-json {a.from_json} is not under {RESULTS} (a table's rows name their raw output there)")
        add_to_table(a.table, json.loads(source.read_text()), source.relative_to(RESULTS).as_posix(), a.date,
                     a.commit)
        return
    if not a.peer.is_file():
        fail(f"--peer {a.peer} is not a file (the DualSPHysics CPU build's run.sh)")
    if a.steps < 1 or a.warmup < 1 or a.threads < 1 or a.tmax <= 0:
        fail("--steps, --warmup and --threads must be at least 1 and --tmax positive")
    runs, ratios = [], []
    for dp in a.dp:
        order = ["peer", "float32", "float64", "float64", "float32", "peer"]
        got = []
        for k, what in enumerate(order, 1):
            rec = run_peer(a.peer, dp, a.tmax, a.threads) if what == "peer" else \
                run_shoal(dp, what, a.steps, a.warmup, a.threads)
            rec.update(dp=dp, order=k, threads=a.threads)
            got.append(rec)
            label = f"DualSPHysics ({rec['build']})" if what == "peer" else f"shoal {what}"
            print(f"dp {dp}  {k}  {label:<26} {rec['particles']:>9,} particles  "
                  f"{rec['particle_steps_per_second']:>12,.0f} particle-steps/s", flush=True)
        peer = sum(r["particle_steps_per_second"] for r in got if r["code"] == "DualSPHysics")
        for precision in ("float32", "float64"):
            mine = sum(r["particle_steps_per_second"] for r in got if r.get("precision") == precision)
            ratios.append({"dp": dp, "precision": precision, "shoal_over_peer": mine / peer})
            print(f"dp {dp}  shoal {precision} / DualSPHysics: {mine / peer:.2f}")
        runs += got
    sitting = {"runs": runs, "ratios": ratios, "steps": a.steps, "tmax": a.tmax}
    if a.json:
        a.json.write_text(json.dumps(sitting, indent=2) + "\n")
    if a.table:
        if not a.json or RESULTS not in a.json.resolve().parents:
            fail(f"--table needs --json FILE under {RESULTS} (the rows name their raw output)")
        add_to_table(a.table, sitting, a.json.resolve().relative_to(RESULTS).as_posix(), a.date, a.commit)


if __name__ == "__main__":
    main()
