"""The ``shoal`` command line.

    shoal run [CASE | FILE.toml] [--dp M] [--end-time S] [--output-interval S] [--out DIR]
              [--precision float32|float64] [--backend cpu|cuda] [--integrator NAME] [--param KEY=VALUE]
              [--checkpoint-interval S]
    shoal run --resume RUN_DIR [--end-time S]    continue a stopped run from its newest checkpoint
    shoal check CASE | FILE.toml     validate; print particle counts, memory and the time step
    shoal new NAME [-o FILE.toml]    write a commented case file of a built-in case to start from
    shoal plot-case CASE | FILE.toml [-o FILE.png]
    shoal post RUN_DIR [--gauges] [--spectra] [--mean-flow] [--tracks] [--plane AXIS=VALUE] [--out DIR]
    shoal validate [CASE ...] [--quick | --full] [--backend cpu|cuda] [--out DIR]
    shoal validate --report-only [CASE ...] --from DIR [--from DIR ...] --out DIR   merge saved results
    shoal cases
    shoal info
    shoal --version

Bad input prints one line ``shoal: error: ...`` and exits with status 2;
a run that goes unstable prints where and why and exits with status 3;
a run stopped by SIGINT/SIGTERM writes a checkpoint and exits with 130/143
(``shoal run --resume RUN_DIR`` continues it); a full disk exits with 4; a
file the system refuses to read or write (permissions, a missing file) exits
with 2, in one line.
"""

from __future__ import annotations

import argparse
import inspect
import os
import sys
from pathlib import Path

from .environment import numba_environment_error
from .errors import InputError, InstabilityError, OutputError, RunInterrupted

DEFAULT_CASE = "dam-break-2d"


def _printable(text):
    """`text` on one line: a control character (a newline in a file name) or an undecodable byte of an
    argument shown escaped, as repr shows it, so an error stays one line and sends the terminal no escape."""
    return "".join(c if c.isprintable() else repr(c)[1:-1] for c in str(text))


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # one line, exit 2 (argparse prints usage first otherwise)
        sys.stderr.write(f"shoal: error: {_printable(message)}\n")
        raise SystemExit(2)


def _positive_float(name):
    def conv(text):
        try:
            if "_" in text:  # float() reads 0_05 as 5: a typo, not a number
                raise ValueError
            v = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} must be a number, got {text!r}") from None
        if not v > 0 or v != v or v == float("inf"):
            raise argparse.ArgumentTypeError(f"{name} must be a positive number, got {text!r}")
        return v
    return conv


def build_parser():
    from .version import __version__

    p = _Parser(prog="shoal", description="Weakly-compressible SPH for free-surface coastal and hydraulic flows.")
    p.add_argument("--version", action="version", version=f"shoal {__version__}")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)
    r = sub.add_parser("run", help="run a built-in case or a case file (default: the 2D dam-break demo)")
    r.add_argument("case", nargs="?", default=None,
                   help=f"built-in case name (see `shoal cases`) or a TOML case file (default: {DEFAULT_CASE})")
    _case_args(r)
    r.add_argument("--out", default=None, help="output directory (default: runs/CASE)")
    r.add_argument("--backend", default="cpu", help="compute backend: cpu (default) or cuda")
    r.add_argument("--overwrite", action="store_true", help="replace a run already in the output directory")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.add_argument("--no-plot", action="store_true", help="no PNG of the final state")
    r.add_argument("--resume", default=None, metavar="RUN_DIR",
                   help="continue the run in RUN_DIR from its newest valid checkpoint (with --end-time: extend it)")
    r.add_argument("--checkpoint-interval", type=_positive_float("--checkpoint-interval"), default=None,
                   metavar="SECONDS", help="simulated time between checkpoints [s] (also: [checkpoint] in a case "
                                           "file; default: every 15 min of wall-clock time)")
    c = sub.add_parser("check", help="validate a case; print particle counts, memory estimate and time step")
    c.add_argument("case", help="built-in case name or a TOML case file")
    _case_args(c)
    n = sub.add_parser("new", help="write a commented TOML case file of a built-in case to start from")
    n.add_argument("name", help="built-in case name (see `shoal cases`)")
    n.add_argument("-o", "--output", default=None, help="file to write (default: NAME.toml)")
    n.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="a parameter of the built-in case (repeatable), e.g. --param inflow_speed=0.7")
    n.add_argument("--dp", type=_positive_float("--dp"), help="particle spacing [m]")
    n.add_argument("--force", action="store_true", help="replace an existing file")
    pc = sub.add_parser("plot-case", help="write a PNG of a case's particles (side and plan views)")
    pc.add_argument("case", help="built-in case name or a TOML case file")
    pc.add_argument("-o", "--output", default=None, help="PNG to write (default: CASE_case.png)")
    _case_args(pc)
    po = sub.add_parser("post", help="standard plots of a finished run (PNGs in RUN_DIR/post/), free-surface meshes")
    po.add_argument("run_dir", help="output directory of a run")
    po.add_argument("--out", default=None, help="folder for the PNGs (default: RUN_DIR/post)")
    po.add_argument("--gauges", action="store_true", help="time series of the gauge, max-z, run-up and probe files")
    po.add_argument("--spectra", action="store_true",
                    help="wave spectra of the gauges (Welch) against the paddle's target spectrum; Hm0, Tp, Tm01, "
                         "Tm02 in spectra.json")
    po.add_argument("--segment", type=_positive_float("--segment"), default=None, metavar="SECONDS",
                    help="Welch segment length of --spectra (default: a quarter of the record)")
    po.add_argument("--mean-flow", action="store_true",
                    help="period-mean current, set-up and profiles from the test-point grids")
    po.add_argument("--tracks", action="store_true", help="trajectories of the tracked particles")
    po.add_argument("--plane", default=None, metavar="AXIS=VALUE",
                    help="|v| of the particles within dp of a plane, e.g. z=0.05 or y=0.15 (mid: the middle y plane)")
    po.add_argument("--time", type=float, default=None, help="snapshot time for --plane [s] (default: the last)")
    po.add_argument("--period", type=_positive_float("--period"), default=None,
                    help="averaging period [s] (default: the case's piston period, else the whole record)")
    po.add_argument("--periods", type=int, default=None, help="average over the last N periods (default: all)")
    po.add_argument("--start", type=float, default=None,
                    help="ignore the record before this time [s] (spectra: default the paddle's ramp)")
    po.add_argument("--isosurface", action="store_true",
                    help="the free surface of every snapshot as a mesh (VTK, ParaView): isosurface/ in the output "
                         "folder (only when asked for)")
    po.add_argument("--iso-spacing", type=_positive_float("--iso-spacing"), default=None, metavar="METRES",
                    help="grid spacing of the iso-surface (default dp/2)")
    po.add_argument("--iso-level", type=float, default=0.5,
                    help="kernel-sum level of the iso-surface, 0 < level < 1 (default 0.5: the free surface)")
    po.add_argument("--backend", default="cpu", help="backend of the iso-surface's kernel sums: cpu or cuda")
    va = sub.add_parser("validate", help="run the validation cases against reference data; write a report "
                                         "(REPORT.md, REPORT.html, PNGs)")
    va.add_argument("cases", nargs="*", metavar="CASE",
                    help="validation cases to run (default: all; `shoal validate --list` names them)")
    mode = va.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_true", help="the quick resolutions (default; ~15 min on 2 cores)")
    mode.add_argument("--full", action="store_true", help="the finer resolutions (hours on 2 cores; GPU recommended)")
    va.add_argument("--backend", default="cpu", help="compute backend: cpu (default) or cuda")
    va.add_argument("--out", default="runs/validate",
                    help="folder for REPORT.md, REPORT.html, results.json and figures/ (default: runs/validate; "
                         "--out validation regenerates the committed report)")
    va.add_argument("--list", action="store_true", help="list the validation cases and exit")
    va.add_argument("--report-only", action="store_true",
                    help="run nothing: rebuild the report in --out from saved results (its own results.json, then "
                         "each --from folder's, an entry replacing the one of the same case; CASE names restrict "
                         "what is taken from --from)")
    va.add_argument("--from", dest="sources", action="append", default=[], metavar="DIR",
                    help="with --report-only: a folder written by shoal validate --out (results.json, figures/); "
                         "repeatable")
    sub.add_parser("cases", help="list the built-in cases")
    sub.add_parser("info", help="show the backends available here")
    return p


def _case_args(r):
    r.add_argument("--dp", type=_positive_float("--dp"), help="particle spacing [m]")
    r.add_argument("--end-time", type=_positive_float("--end-time"), help="simulated time [s]")
    r.add_argument("--output-interval", type=_positive_float("--output-interval"),
                   help="time between snapshots [s]")
    r.add_argument("--precision", choices=["float32", "float64"], default=None)
    r.add_argument("--integrator", choices=["verlet", "symplectic", "predictor_corrector"], default=None)
    r.add_argument("--kernel", choices=["wendland", "cubic"], default=None)
    r.add_argument("--param", action="append", default=[], metavar="KEY=VALUE",
                   help="a parameter of a built-in case (repeatable), e.g. --param inflow_speed=0.7 "
                        "(see `shoal cases`)")
    r.add_argument("--option", action="append", default=[], metavar="KEY=VALUE",
                   help="an SPH option (repeatable; any key of the case file's [options] table), "
                        "e.g. --option alpha=0.02 --option wall_pressure=adami")
    r.add_argument("--half", action="store_true",
                   help="tidal-bore cases: model half the width with a symmetry plane (--param half=true)")


def _parse_params(items, flag="--param", example="inflow_speed=0.7"):
    """--param (or `flag`) KEY=VALUE items -> dict, values parsed as TOML (numbers, booleans, strings)."""
    import tomllib

    from .casefile import wide_integer

    out = {}
    for item in items:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key.isidentifier():
            raise InputError(f"{flag} {item!r} must look like KEY=VALUE, e.g. {flag} {example}")
        try:
            text.encode("utf-8")
        except UnicodeEncodeError:  # a byte of the argument that is not UTF-8 (a surrogate escape)
            raise InputError(f"{flag} {key}=...: the value holds a byte that is not UTF-8 (the case file it goes "
                             "into is UTF-8 text); give UTF-8 text") from None
        try:
            out[key] = tomllib.loads(f"v = {text.strip()}")["v"]
        except ValueError:  # TOMLDecodeError, or an integer of more than 4300 digits (int()'s limit)
            out[key] = text.strip()  # a bare word: a string
        if wide_integer(out[key]) is not None:  # (as in a case file: one of thousands of digits cannot be written)
            raise InputError(f"{flag} {key}=...: an integer beyond 64 bits; TOML integers are 64-bit, from -2^63 "
                             "to 2^63 - 1")
    return out


def _is_file(name):
    return name.endswith(".toml") or "/" in name or Path(name).is_file()


def _get_case_checked(get_case, name, kwargs, params):
    """get_case(name, **kwargs), a --param value of the wrong kind being one line of InputError."""
    from pydantic import ValidationError

    from .casefile import format_validation_error

    given = ", ".join(f"{k}={v!r}" for k, v in params.items())
    try:
        return get_case(name, **kwargs)
    except ValidationError as err:
        raise InputError(f"case {name!r}{f' with --param {given}' if params else ''}: "
                         f"{format_validation_error(err)}") from None
    except InputError:
        raise
    except (TypeError, AttributeError, ValueError) as err:  # (ValueError: float('cubic') in a case function)
        if not params:
            raise
        raise InputError(f"case {name!r}: a --param value has the wrong kind ({given}): "
                         f"{str(err).splitlines()[0]}") from None


def _make_case(args):
    from .cases import CASES, get_case

    params = _parse_params(getattr(args, "param", []))
    if getattr(args, "half", False):
        params["half"] = True
    if _is_file(args.case):
        from .casefile import load_case

        if params:
            raise InputError("--param sets parameters of built-in cases; edit the case file instead")
        over = {}
        if args.dp is not None:
            over["dp"] = args.dp
        if args.end_time is not None:
            over["end_time"] = args.end_time
        case = load_case(args.case, overrides=over)
        if args.output_interval is not None:
            case = case.model_copy(update={"output": case.output.model_copy(update={"interval": args.output_interval})})
            case.revalidate()
    else:
        if args.case not in CASES:
            raise InputError(f"unknown case {args.case!r}; built-in cases: {', '.join(CASES)} "
                             "(or give a path to a .toml case file)")
        kwargs = dict(params)
        if args.dp is not None:
            kwargs["dp"] = args.dp
        if args.output_interval is not None:
            kwargs["output_interval"] = args.output_interval
        if args.end_time is not None:
            kwargs["end_time"] = args.end_time
        case = _get_case_checked(get_case, args.case, kwargs, params)
    changes = {k: getattr(args, k) for k in ("precision", "integrator", "kernel") if getattr(args, k, None) is not None}
    changes.update(_parse_options(getattr(args, "option", [])))
    if changes:
        case = case.with_options(**changes)
    return case


def _parse_options(items):
    """--option KEY=VALUE items -> SPHOptions changes, each key and value's type checked (one-line errors)."""
    from .options import SPHOptions

    parsed = _parse_params(items, flag="--option", example="alpha=0.02")
    try:
        SPHOptions.check_types(parsed)
    except InputError as err:
        raise InputError(f"--option: {err}") from None
    return parsed


def _cmd_resume(args):
    from .runner import resume_run

    fixed = [opt for opt, v in (("a case", args.case), ("--dp", args.dp), ("--output-interval", args.output_interval),
                                ("--precision", args.precision), ("--integrator", args.integrator),
                                ("--kernel", args.kernel), ("--param", args.param), ("--option", args.option),
                                ("--half", args.half),
                                ("--out", args.out), ("--overwrite", args.overwrite)) if v]
    if fixed:
        raise InputError(f"--resume continues the run in {args.resume} with its own case; {', '.join(fixed)} cannot "
                         "be given with it (--end-time and --checkpoint-interval can)")
    out = Path(args.resume)
    if not out.is_dir():
        raise InputError(f"--resume {args.resume}: no such run directory")
    print(f"shoal: resuming {out}")
    try:
        res = resume_run(out, end_time=args.end_time, checkpoint_interval=args.checkpoint_interval,
                         backend=args.backend, progress=not args.no_progress and sys.stderr.isatty(),
                         plot=not args.no_plot)
    except KeyboardInterrupt as err:
        err.shoal_message = f"aborted; the run's checkpoints are kept (resume with shoal run --resume {out})"
        raise
    print(f"shoal: resumed from {res.resumed_from.name}; now at step {res.steps}, t = {res.time:.4g} s "
          f"({res.wall_seconds:.1f} s wall in all); {res.snapshots} snapshots in {res.out_dir}/; "
          f"escaped particles: {res.escaped}")
    return 0


def _interrupted_start(out, case):
    """What to say of a new run interrupted outside its time loop (Ctrl-C while the particles are generated
    or the kernels compiled; in the loop a signal ends the run with a checkpoint): with a checkpoint, how to
    resume; without one, the files the start wrote are removed, so the case runs again without --overwrite."""
    from .simulation.checkpoint import list_checkpoints
    from .simulation.resume import list_manifests
    from .simulation.run_files import clear_run

    if out.is_dir() and (list_checkpoints(out) or list_manifests(out)):
        return f"aborted; snapshots and checkpoints written so far are kept (resume with shoal run --resume {out})"
    if any(out.glob(f"{case.name}_[0-9]*")):  # the time loop had started: keep what it wrote
        return (f"aborted before the run's first checkpoint: nothing to resume; the snapshots written so far "
                f"are kept in {out} (run again with --overwrite to start over)")
    if out.is_dir() and (out / "resolved.json").exists():
        clear_run(out, case)
        lock = out / ".shoal.lock"
        if lock.exists():
            lock.unlink()
        if not any(out.iterdir()):
            out.rmdir()
    return "aborted before the run's first checkpoint: nothing to resume and nothing kept; run it again to start over"


def cmd_run(args):
    from .backends import check_backend
    from .runner import run_case

    check_backend(args.backend)
    if args.resume is not None:
        return _cmd_resume(args)
    if args.case is None:
        args.case = DEFAULT_CASE
    case = _make_case(args)
    if args.checkpoint_interval is not None:
        case = case.model_copy(update={"checkpoint": case.checkpoint.model_copy(
            update={"interval": args.checkpoint_interval})})
    out = args.out or f"runs/{case.name}"
    if not args.overwrite and (Path(out) / "resolved.json").exists():
        raise InputError(f"{out} already holds a run (resolved.json); choose another --out directory "
                         "or pass --overwrite")
    print(f"shoal: {case.name}: {case.n_particles} particles ({case.n_fluid} fluid), dp = {case.dp:g} m, "
          f"t_end = {case.end_time:g} s, {case.options.precision}, backend {args.backend}")
    try:
        res = run_case(case, out, backend=args.backend, progress=not args.no_progress and sys.stderr.isatty(),
                       plot=not args.no_plot, overwrite=args.overwrite)
    except KeyboardInterrupt as err:
        err.shoal_message = _interrupted_start(Path(out), case)
        raise
    print(f"shoal: {res.steps} steps to t = {res.time:.4g} s in {res.wall_seconds:.1f} s "
          f"({res.compile_seconds:.1f} s compiling), {res.particle_steps_per_second:.3g} particle-steps/s; "
          f"{res.snapshots} snapshots in {res.out_dir}/ ({case.name}.pvd); escaped particles: {res.escaped}")
    return 0


def cmd_check(args):
    from .check import check_case

    case = _make_case(args)
    for line in check_case(case):
        print(line)
    return 0


def cmd_new(args):
    from .casefile import write_case
    from .cases import CASES, get_case

    if args.name not in CASES:
        raise InputError(f"unknown case {args.name!r}; built-in cases: {', '.join(CASES)}")
    params = _parse_params(args.param)
    kwargs = dict(params)
    if args.dp is not None:
        kwargs["dp"] = args.dp
    case = _get_case_checked(get_case, args.name, kwargs, params)  # a --param of the wrong kind: one line
    out = Path(args.output or f"{args.name}.toml")
    if out.exists() and not args.force:
        raise InputError(f"{out} exists; choose another file with -o or pass --force")
    write_case(case, out)
    print(f"shoal: wrote {out} (the {args.name} case); edit it, then: shoal check {out} && shoal run {out}")
    return 0


def cmd_plot_case(args):
    from .output.plot_case import plot_case

    case = _make_case(args)
    p = case.particles()
    out = Path(args.output or f"{case.name}_case.png")
    names = [s.name or f"solid{i}" for i, s in enumerate(case.solids)]
    plot_case(out, p.positions, p.kinds, body=p.body, body_names=names, dim=case.dim,
              title=f"{case.name}: dp = {case.dp:g} m, {len(p):,} particles", dp=case.dp)
    print(f"shoal: wrote {out}")
    return 0


def cmd_post(args):
    from .post import post

    if args.isosurface:
        from .backends import check_backend

        check_backend(args.backend)
    written = post(args.run_dir, out=args.out, gauges=args.gauges, mean_flow=args.mean_flow, tracks=args.tracks,
                   plane=args.plane, time=args.time, period=args.period, periods=args.periods, start=args.start,
                   isosurface=args.isosurface, iso_spacing=args.iso_spacing, iso_level=args.iso_level,
                   backend=args.backend, spectra=args.spectra, segment=args.segment)
    pngs = sum(p.suffix == ".png" for p in written)
    print(f"shoal: wrote {pngs} PNG(s)" + (f" and {len(written) - pngs} iso-surface file(s)" if args.isosurface
                                           else "") + ":")
    for path in written:
        print(f"  {path}")
    return 0


def cmd_validate(args):
    from .backends import check_backend
    from .validation import VALIDATION_CASES, get_cases, run_validation

    if args.list:
        for name, case in VALIDATION_CASES.items():
            print(f"{name:24s} {case.title}")
        return 0
    cases = get_cases(args.cases)  # an unknown name: InputError (one line, exit 2)
    if args.sources and not args.report_only:
        raise InputError("--from goes with --report-only (a report merged from saved results)")
    if args.report_only:
        from .validation.report import merge_reports

        if args.full:
            raise InputError("--report-only runs nothing: --full does not apply (each saved entry keeps its mode)")
        command = "shoal validate --report-only " + " ".join(
            [*args.cases, *(f"--from {s}" for s in args.sources), f"--out {args.out}"])
        results = merge_reports(args.sources, args.out, cases=args.cases or None, command=command)
        print(f"shoal: validation report in {Path(args.out) / 'REPORT.md'} (and REPORT.html), merged from saved "
              "results; " + ", ".join(f"{r.case} {r.verdict}" for r in results))
        return 0
    check_backend(args.backend)
    command = "shoal validate " + " ".join([*args.cases, "--full" if args.full else "--quick",
                                            *(["--backend", args.backend] if args.backend != "cpu" else [])])
    results = run_validation(cases if args.cases else None, quick=not args.full, backend=args.backend, out=args.out,
                             command=command)
    failed = [r.case for r in results if r.verdict == "FAIL"]
    print(f"shoal: validation report in {Path(args.out) / 'REPORT.md'} (and REPORT.html); "
          + ", ".join(f"{r.case} {r.verdict}" for r in results))
    return 1 if failed else 0


def cmd_cases(args):
    from .cases import CASES

    for name, fn in CASES.items():
        doc = inspect.getdoc(fn) or ""
        print(f"{name:26s} {doc.splitlines()[0] if doc else ''}")
    return 0


def cmd_info(args):
    import numba

    from .version import __version__

    print(f"shoal {__version__}")
    from .backends.cuda import cuda_status

    print(f"cpu: available, {numba.get_num_threads()} threads (numba {numba.__version__}, "
          f"threading layer chosen at the first parallel loop)")
    ok, why = cuda_status()
    if ok:
        print(f"cuda: available: {why}")
        try:
            from numba import cuda

            for d in cuda.gpus:
                with d:
                    free, total = cuda.current_context().get_memory_info()
                print(f"  device {d.id}: {d.name}, {total / 2**30:.1f} GiB ({free / 2**30:.1f} GiB free)")
        except Exception:  # the simulator has no memory figures
            pass
        _info_mpi_gpus()
    else:
        print(f"cuda: not available: {why}")
    return 0


def _info_mpi_gpus():
    """`shoal info` under mpiexec with the CUDA backend available: the device each rank would use
    (`shoal.parallel.gpu`); outside MPI, the rule."""
    from .parallel import world

    comm = world()
    if comm is None:
        print("  under mpiexec (--backend cuda) each rank uses the device (its rank on the node) mod (the devices "
              "it sees)")
        return
    from .parallel.gpu import describe, select_device

    assignment = select_device(comm, activate=False)
    print(f"  under mpiexec with {comm.Get_size()} ranks, --backend cuda would use:")
    for line in describe(assignment):
        print(f"    {line}")


def main(argv=None):
    import signal

    from .environment import interrupted_while_starting
    from .parallel import quiet_other_ranks

    if signal.getsignal(signal.SIGINT) is interrupted_while_starting:  # loaded: Ctrl-C is KeyboardInterrupt again
        signal.signal(signal.SIGINT, signal.default_int_handler)

    quiet_other_ranks()  # under mpiexec: messages from rank 0 only
    # a file name with a byte that is not UTF-8 (a surrogate escape in argv) is printed escaped, not a
    # UnicodeEncodeError (stdout is strict under UTF-8 locales other than C.UTF-8)
    for stream in (sys.stdout, sys.stderr):
        if getattr(stream, "errors", None) == "strict" and hasattr(stream, "reconfigure"):
            stream.reconfigure(errors="backslashreplace")
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # argparse: --help (0) or a one-line error (2)
        return exc.code
    if args.command is None:
        parser.print_help()
        return 0
    try:
        bad = numba_environment_error(os.environ)
        if bad:
            raise InputError(bad)
        return {"run": cmd_run, "cases": cmd_cases, "info": cmd_info, "check": cmd_check, "new": cmd_new,
                "plot-case": cmd_plot_case, "post": cmd_post, "validate": cmd_validate}[args.command](args)
    except InputError as err:
        sys.stderr.write(f"shoal: error: {_printable(err)}\n")
        return 2
    except InstabilityError as err:
        sys.stderr.write(f"shoal: run stopped: {err}\n")
        return 3
    except RunInterrupted as err:
        sys.stderr.write(f"shoal: {err}\n")
        return err.exit_status
    except OutputError as err:
        sys.stderr.write(f"shoal: error: {_printable(err)}\n")
        return 4
    except BrokenPipeError:  # the reader went away (shoal cases | head -1): end quietly, as a killed writer
        try:
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # the flush at exit fails no more
        except OSError:
            pass
        return 141
    except OSError as err:  # a file the command reads or writes, refused by the system
        from .simulation.resources import DISK_FULL

        name = str(getattr(err, "filename", None) or "")
        name = name if len(name) <= 200 else name[:100] + "..." + name[-60:]
        what = f"{err.strerror or err}" + (f": {name}" if name else "")
        sys.stderr.write(f"shoal: error: {_printable(what)}\n")
        return 4 if err.errno in DISK_FULL else 2
    except KeyboardInterrupt as err:
        signum = getattr(err, "signum", 2)
        sys.stderr.write(f"shoal: {getattr(err, 'shoal_message', 'aborted')}\n")
        return 128 + signum


if __name__ == "__main__":
    sys.exit(main())
