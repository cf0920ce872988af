"""The ``ddgsa`` command: ``run``, ``validate``, ``models``, ``report``, ``html``, ``export``, ``bench``, ``modes``.

Exit codes: 0 success; 1 a failure while running (also: the output folder is busy with
another run); 2 invalid input (study file, options, an output folder of another study);
3 the run finished but a requested output's indices are refused or untrusted by every method
(or sweep evaluations failed) -- the report is written and says why; ``--allow-untrusted``
turns this into 0; 130 interrupted (Ctrl-C). Errors print one clear message and no traceback
(``--verbose`` adds it). ``-q``/``-v`` go before or after the subcommand.
"""

from __future__ import annotations

import argparse
import json
import logging
import shutil
import sys
import traceback
import warnings
from pathlib import Path
from typing import TYPE_CHECKING

from ddgsa.errors import DdgsaError, StoreCorruptError, StoreWriteError

if TYPE_CHECKING:                      # the CLI imports the heavy modules only when a command needs them
    from ddgsa.execute.kinds.common import StudyResult
    from ddgsa.study.spec import Study

EXIT_OK, EXIT_FAILURE, EXIT_INPUT, EXIT_UNTRUSTED, EXIT_INTERRUPTED = 0, 1, 2, 3, 130


def _common() -> argparse.ArgumentParser:
    """``-q`` and ``-v``, accepted before and after the subcommand."""
    c = argparse.ArgumentParser(add_help=False)
    c.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                   help="no progress bar or notes, only warnings and errors")
    c.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                   help="tracebacks and debug messages")
    return c


def _parser() -> argparse.ArgumentParser:
    common = _common()
    p = argparse.ArgumentParser(prog="ddgsa", description="Global sensitivity analysis of wind-turbine drive trains.",
                                parents=[common],
                                epilog="exit codes: 0 ok, 1 failure while running or output folder busy, 2 invalid "
                                       "input, 3 the report is written but some (scene, output) is unconfirmed: no method trusts or "
                                       "rank-confirms it, nor is it nothing to rank (confirmation.csv; --allow-untrusted "
                                       "exits 0), 130 interrupted")
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a study and write its report", parents=[common])
    run.add_argument("study", type=Path)
    run.add_argument("--out", type=Path, help="output folder (default runs/<study name>)")
    run.add_argument("--force", action="store_true",
                     help="write into a folder that holds another study's results (its stale files are removed)")
    run.add_argument("--allow-untrusted", action="store_true",
                     help="exit 0 even when some (scene, output) is unconfirmed (default: exit 3)")
    run.add_argument("--jobs", type=int, help="parallel workers (default from the study's run.jobs, else the "
                                              "number of cores)")
    run.add_argument("--retry-failed", action="store_true",
                     help="run again the evaluations the folder's store holds as failed (after fixing their cause; "
                          "by default a failure is kept with its reason and not rerun)")
    run.add_argument("--confirm-time", metavar="TIME",
                     help="spend at most this wall time confirming what the methods left unconfirmed, cheapest "
                          "pairs first (e.g. '10 min'; sets or adds the study's confirm: {time: ...}, kind gsa)")
    run.add_argument("--backend", choices=["loky", "dask"], help="joblib loky (default) or a Dask cluster")
    run.add_argument("--address", help="Dask scheduler HOST:PORT (default: a LocalCluster)")
    val = sub.add_parser("validate", help="check a study file; exit 0 or 2", parents=[common])
    val.add_argument("study", type=Path)
    mods = sub.add_parser("models", help="list models, fidelities, parameters and outputs (units, meanings)",
                          parents=[common])
    mods.add_argument("name", nargs="?", help="one model (default: all)")
    rep = sub.add_parser("report", help="rebuild tables and plots from a run's stored evaluations", parents=[common])
    rep.add_argument("dir", type=Path)
    rep.add_argument("--allow-untrusted", action="store_true", help="exit 0 even with untrusted results")
    htm = sub.add_parser("html", help="write report.html into each results folder from the files stored there "
                                      "(no evaluation store needed)", parents=[common])
    htm.add_argument("dirs", type=Path, nargs="+", metavar="DIR")
    exp = sub.add_parser("export", help="a results folder's indices, bounds, flags, moments and fault statistics as "
                                        "labelled arrays (xarray; NetCDF, Zarr or tidy CSV)", parents=[common])
    exp.add_argument("dir", type=Path)
    exp.add_argument("--format", choices=["netcdf", "zarr", "csv"], default="netcdf")
    exp.add_argument("--out", type=Path, help="where to write (default DIR/indices.nc, DIR/indices.zarr or "
                                              "DIR/indices_long.csv)")
    ben = sub.add_parser("bench", help="speed of each fidelity (default), accuracy against cost of each method, "
                                       "the calibration of every method's trusted flag, scaling, or the indirect drive",
                         parents=[common])
    ben.add_argument("what", nargs="?", choices=["speed", "accuracy", "trust", "scaling", "indirect", "rig"],
                     default="speed",
                     help="speed: every speed target with its measured value and verdict; accuracy: index error "
                          "against evaluations and wall time; trust: false-trust and false-alarm rates of every "
                          "method on 15 reference functions x 20 seeds; scaling: wall time against runs, "
                          "parameters and workers (all but speed and indirect written to --out); indirect: the indirect "
                          "drive's fidelities against their references; rig: the test rig's linear paths against the "
                          "nonlinear rig, and its speed against its accuracy (block, per-point linear, kloss; chart)")
    ben.add_argument("--out", type=Path, default=None,
                     help="folder for the CSVs and charts (default results/accuracy_cost, results/trust_calibration, "
                          "results/scaling or results/rig_speed)")
    ben.add_argument("--held-out", action="store_true",
                     help="trust: only the held-out suite of twelve drawn block-sum functions (issue 51's targets: "
                          "false trust of trusted rows, auto at 1 000 runs, M-DRM's share; ddgsa.bench.heldout)")
    ben.add_argument("--ranking", action="store_true",
                     help="trust: only the ranking rule's functions (exact and near ties, 36 inert inputs of 40): false "
                          "rank and tie confirmations of every method (issue 51)")
    ben.add_argument("--quick", action="store_true",
                     help="small problems: checks the bench itself (accuracy: Saltelli/RBD-FAST up to 2^10, "
                          "2 seeds, no drive train; trust: 7 functions x 3 seeds; speed: 60 s scene, shortened "
                          "study; scaling: small sizes)")
    ben.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    ben.add_argument("--ref-seconds", type=float, default=20.0, help="scene seconds the slow reference integrates")
    ben.add_argument("--no-study", action="store_true", help="speed: skip the paper_c_structural study rows")
    mod = sub.add_parser("modes", help="natural frequencies of a model or a study's model (CSV + PNG); "
                                       "--campbell: against rotor speed", parents=[common])
    mod.add_argument("target", help="a model name (see ddgsa models) or a study YAML file")
    mod.add_argument("--campbell", action="store_true", help="modes against rotor speed with order lines")
    mod.add_argument("--max-rpm", type=float, default=20.0, help="highest rotor speed of the Campbell diagram [rpm]")
    mod.add_argument("--points", type=int, default=11, help="rotor speeds from 0 to --max-rpm")
    mod.add_argument("--orders", type=float, nargs="+", default=[1.0, 3.0], help="excitation orders (1P, 3P ...)")
    mod.add_argument("--out", type=Path, help="output folder (default runs/modes_<name>)")
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script."""
    args = _parser().parse_args(argv)
    args.quiet, args.verbose = getattr(args, "quiet", False), getattr(args, "verbose", False)
    logging.basicConfig(level=logging.DEBUG if args.verbose else logging.WARNING, format="%(message)s")
    shown = warnings.showwarning
    warnings.showwarning = _show_warning(args.quiet)
    try:
        _check_working_folder()
        return _dispatch(args)
    except DdgsaError as exc:
        if args.verbose:
            traceback.print_exc()
        print(f"ddgsa: error: {bounded(str(exc))}", file=sys.stderr)
        return EXIT_INPUT if isinstance(exc, ValueError) else EXIT_FAILURE
    except KeyboardInterrupt:
        print("ddgsa: interrupted; finished batches are stored, rerun to resume", file=sys.stderr)
        return EXIT_INTERRUPTED
    except Exception as exc:  # noqa: BLE001 -- the CLI reports, it does not crash
        if args.verbose:
            traceback.print_exc()
        print(f"ddgsa: failed: {type(exc).__name__}: {bounded(str(exc))} (rerun with --verbose for the traceback)",
              file=sys.stderr)
        return EXIT_FAILURE
    finally:
        warnings.showwarning = shown


def _check_working_folder() -> None:
    """Refuse to start in a working folder that was deleted: every relative path (a study, ``--out``,
    the default ``runs/<study>``) would fail later as a bare ``FileNotFoundError`` naming no file.

    Raises
    ------
    WorkingFolderError
        Naming the folder (the shell's ``$PWD``) and the way out.
    """
    import os

    from ddgsa.errors import WorkingFolderError

    try:
        os.getcwd()
    except FileNotFoundError:
        gone = os.environ.get("PWD") or "the current folder"
        raise WorkingFolderError(f"{gone}: the working folder was deleted after this shell entered it, so relative "
                                 "paths (and the default output folder runs/<study>) cannot be resolved; cd to an "
                                 "existing folder and rerun") from None


MESSAGE_LINES, MESSAGE_LINE_CHARS = 20, 600
"""An error message prints at most this many lines of at most this many characters."""


def bounded(message: str) -> str:
    """``message`` cut to :data:`MESSAGE_LINES` lines of :data:`MESSAGE_LINE_CHARS` characters (the
    last line says how many more problems there were): a hostile input never floods the terminal."""
    lines = message.splitlines() or [""]
    more = len(lines) - MESSAGE_LINES
    cut = MESSAGE_LINE_CHARS - 3
    lines = [ln if len(ln) <= MESSAGE_LINE_CHARS else ln[:cut] + "..." for ln in lines[:MESSAGE_LINES]]
    return "\n".join(lines + ([f"... and {more} more lines"] if more > 0 else []))


def _dispatch(args: argparse.Namespace) -> int:
    if args.command == "validate":
        from ddgsa.study.checks import SAMPLE, support_points

        study = _load(args.study, args.quiet)
        sc = study.spec.scenes
        print(f"{args.study}: valid ({study.spec.kind} study '{study.name}', model {study.spec.model.name}, "
              f"{plural(len(study.spec.parameters), 'parameter')}, {plural(len(sc.grid()), 'scene')} x "
              f"{plural(sc.realisations, 'realisation')})")
        if not args.quiet:
            support = (f"{plural(len(support_points(study)), 'point')} of the parameters' support ({SAMPLE} of "
                       "them sampled), " if study.space is not None else "")      # a sweep has no support to check
            print(f"checked: the sampling of every scene, {support}parameters without effect, units")
        return EXIT_OK
    if args.command == "models":
        _print_models(args.name)
        return EXIT_OK
    if args.command == "run":
        if args.jobs is not None and args.jobs < 1:       # the command line first: before the study loads
            print(f"ddgsa: error: --jobs {args.jobs}: must be >= 1", file=sys.stderr)
            return EXIT_INPUT
        if args.confirm_time is not None:
            from ddgsa.study.spec import confirm_time

            confirm_time(args.confirm_time)
        study = _load(args.study, args.quiet)
        if args.jobs is None and "jobs" not in study.spec.run.model_fields_set:
            args.jobs = default_jobs()
        if args.confirm_time is not None:
            study = study.with_confirm_time(args.confirm_time)
        return _run(study, args)
    if args.command == "report":
        return _report(args)
    if args.command == "bench":
        return _bench(args)
    if args.command == "html":
        from ddgsa.report.html import write_html

        from ddgsa.report.outdir import incompleteness

        for folder in args.dirs:
            path = write_html(folder)
            missing = incompleteness(folder, ignore=(path.name,))
            if missing:
                print(f"ddgsa: warning: {folder}: outputs incomplete: {missing}; {path.name} says so", file=sys.stderr)
            if not args.quiet:
                print(f"wrote {path} ({path.stat().st_size / 1e3:.0f} kB)")
        return EXIT_OK
    if args.command == "export":
        from ddgsa.report.export import export_folder

        path = export_folder(args.dir, args.format, args.out)
        if not args.quiet:
            print(f"wrote {path}")
        return EXIT_OK
    if args.command == "modes":
        return _modes(args)
    return EXIT_INPUT  # pragma: no cover (argparse requires a command)


def _modes(args: argparse.Namespace) -> int:
    """``ddgsa modes``: the model's mode table, or its Campbell diagram (``model.campbell``), as CSV and PNG."""
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from ddgsa import models
    from ddgsa.errors import ModelError
    from ddgsa.mbs.modal import plot_modes
    from ddgsa.study.spec import load_study

    target = Path(args.target)
    if target.suffix in (".yaml", ".yml") or target.exists():
        study = load_study(target)
        model, name = study.make_model(), study.name
    else:
        model, name = models.get(args.target), args.target
    out = args.out or Path("runs") / f"modes_{name}"
    out.mkdir(parents=True, exist_ok=True)
    if not args.campbell:
        from ddgsa.models.basis import TOLERANCE, mode_convergence

        table = model.modes()
        convergence = mode_convergence(model, table)
        if convergence is not None:                  # a flexible shaft: how converged its modes are
            table["basis_error"] = convergence["errors"]
        table.to_csv(out / "modes.csv", index=False)
        what = f"{name}, fidelity {getattr(model, 'fidelity', '') or '-'}, nominal parameters, standing still"
        ax = plot_modes(table)
        ax.set_title(f"natural frequencies: {what}", fontsize=9)
        ax.figure.savefig(out / "modes.png", dpi=120, bbox_inches="tight")
        if not args.quiet:
            print(f"modes of {what}:")
            print(table[[c for c in ("frequency_hz", "damping_ratio", "label", "basis_error") if c in table]]
                  .to_string(index=False))
            if convergence is not None:
                basis = ", ".join(f"{k} {json.dumps(v)}" for k, v in convergence["basis"].items())
                print(f"shaft basis {basis}: every mode below {convergence['below_hz']:.1f} Hz is within "
                      f"{TOLERANCE:.1%} of a converged basis (bending_modes "
                      f"{convergence['reference']['bending_modes']}; basis_error: each mode's distance to it)")
            print(f"wrote {out / 'modes.csv'} and {out / 'modes.png'}")
        return EXIT_OK
    if args.points < 2 or args.max_rpm <= 0:
        raise ModelError(f"--points ({args.points}) must be >= 2 and --max-rpm ({args.max_rpm}) > 0")
    speeds = np.linspace(0.0, args.max_rpm * np.pi / 30.0, args.points)
    diagram = model.campbell(speeds=speeds, orders=args.orders)
    diagram.to_frame().to_csv(out / "campbell.csv", index=False)
    ax = diagram.plot()
    ax.set_title(f"{ax.get_title()}: {name}, fidelity {getattr(model, 'fidelity', '') or '-'}", fontsize=9)
    ax.figure.savefig(out / "campbell.png", dpi=120, bbox_inches="tight")
    from ddgsa.report.html import write_html

    write_html(out)
    if not args.quiet:
        for order in args.orders:
            cross = diagram.crossings(order)
            for _, row in cross.iterrows():
                print(f"{order:g}P crosses mode {row['mode']} at {row['speed_rpm']:.2f} rpm ({row['frequency_hz']:.3g} Hz)")
        print(f"wrote {out / 'campbell.csv'}, {out / 'campbell.png'} and {out / 'report.html'}")
    return EXIT_OK


def _keep_study(source: Path, target: Path, confirm_time: str | None) -> None:
    """Copy the study file into its output folder; with ``--confirm-time`` the copy says
    ``confirm: {time: ...}`` (its comments kept), so ``ddgsa report`` on the folder analyses the runs
    that budget spent instead of dropping them."""
    if confirm_time is None:
        shutil.copyfile(source, target)
        return
    from ruamel.yaml import YAML

    yaml = YAML()                                   # round trip: the user's comments and order stay
    data = yaml.load(source.read_text(encoding="utf-8"))
    if data.get("confirm") is None:
        data["confirm"] = {}
    data["confirm"]["time"] = confirm_time
    with target.open("w", encoding="utf-8") as handle:
        yaml.dump(data, handle)


def _load(path: Path, quiet: bool = False) -> "Study":
    """Load and validate a study and run the model's own checks over it (:mod:`ddgsa.study.checks`).

    Warnings (e.g. a nominal point outside the model's valid region, part of the support that
    will fail) print as ``ddgsa: warning: ...``; notes and hints (a sampling remark, a number
    that looks written in another unit) as ``ddgsa: note/hint: ...`` unless ``quiet``.

    Raises
    ------
    StudyError
        Listing every error of the checks (e.g. a scene the model refuses as aliased).
    """
    from ddgsa.study.checks import evaluation_plan, study_findings
    from ddgsa.errors import StudyError
    from ddgsa.study.spec import StudyWarning, load_study

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", StudyWarning)
        study = load_study(path)
    for w in caught:
        print(f"ddgsa: warning: {w.message}", file=sys.stderr)
    from ddgsa.runner import said_if_slow

    with said_if_slow(f"ddgsa: note: checking model {study.spec.model.name!r} (its modes and sampling; a first "
                      "check after installing compiles the model's kernels: up to three minutes on 2 cores, cached "
                      "for the run)...", quiet):
        findings = study_findings(study)
    errors = [f for f in findings if f.level == "error"]
    if errors:
        raise StudyError("\n".join(f"{path}: {f}" for f in errors))
    for f in findings:
        if f.level == "warning" or not quiet:
            print(f"ddgsa: {f.level}: {path}: {f}", file=sys.stderr)
    plan = evaluation_plan(study)
    if plan and not quiet:
        print(f"ddgsa: note: {plan}", file=sys.stderr)
    return study


def _show_warning(quiet: bool):  # noqa: ANN202 -- returns warnings.showwarning's signature
    """``warnings.showwarning`` for the CLI: ddgsa's own warnings print as one line without the
    source line (``ddgsa: note: ...`` for sampling notes, which ``-q`` hides; ``ddgsa: warning:``
    otherwise); others as Python prints them. Forked workers inherit it."""
    from ddgsa.mbs.sampling import AliasingWarning

    original = warnings.showwarning

    def show(message, category, filename, lineno, file=None, line=None):  # type: ignore[no-untyped-def]
        if not category.__module__.startswith("ddgsa"):
            return original(message, category, filename, lineno, file, line)
        if issubclass(category, AliasingWarning):
            if not quiet:
                print(f"ddgsa: note: {message}", file=sys.stderr)
            return None
        print(f"ddgsa: warning: {message}", file=sys.stderr)
        return None

    return show


def default_jobs() -> int:
    """Workers when neither ``--jobs`` nor the study's ``run.jobs`` says: the cores this process may use."""
    import os

    return max(1, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1))


def plural(n: int, noun: str) -> str:
    """``1 scene``, ``2 scenes``."""
    return f"{n} {noun}{'' if n == 1 else 's'}"


def _run(study: "Study", args: argparse.Namespace) -> int:
    from ddgsa.report.outdir import LOCK_NAME, STORE_NAME, claim, replaced_version, unmark_complete
    from ddgsa.execute.pipeline import default_out, execute
    from ddgsa.runner import EvaluationStore, set_aside

    out = args.out or default_out(study)
    _check_disk(study, out)
    try:
        with claim(out, study.name, force=args.force):
            unmark_complete(out)                    # the folder's outputs are incomplete until its report is written
            old_file = replaced_version(out, study.name, study.digest)
            if old_file is not None:
                print(f"ddgsa: warning: {out}: holds the results of study {study.name!r} from {old_file} with other "
                      f"contents; they are replaced by those of {study.path or 'this study'} (stored evaluations "
                      "with equal keys are reused)", file=sys.stderr)
            if study.path is not None and study.path.resolve() != (out / "study.yaml").resolve():
                _keep_study(study.path, out / "study.yaml", getattr(args, "confirm_time", None))
            try:
                store = EvaluationStore(out / STORE_NAME, watch=[out / LOCK_NAME])
            except StoreCorruptError:
                if not args.force:
                    raise
                aside = set_aside(out / STORE_NAME)
                print(f"ddgsa: warning: the corrupt evaluation store is kept as {aside}; rebuilding {out / STORE_NAME}",
                      file=sys.stderr)
                store = EvaluationStore(out / STORE_NAME, watch=[out / LOCK_NAME])
            try:
                result = execute(study, store, jobs=args.jobs, backend=args.backend, address=args.address,
                                 quiet=args.quiet, retry_failed=args.retry_failed)
                store.check()                       # the store that holds the results is still the folder's
            finally:
                store.close()
            return _finish(result, out, args, "wrote")
    except OSError as exc:
        raise StoreWriteError(_os_failure(exc, out / STORE_NAME)) from None


def _check_disk(study: "Study", out: Path) -> None:
    """Refuse a run whose evaluation store would not fit on the output folder's disk (exit 2)."""
    from ddgsa.errors import StudyError
    from ddgsa.study.limits import gib, run_size

    size = run_size(study.spec, study.space, len(study.outputs))
    where = next(p for p in (out.absolute(), *out.absolute().parents) if p.exists())
    store = out / "evaluations.sqlite"
    free = shutil.disk_usage(where).free + (store.stat().st_size if store.exists() else 0)
    if size.store_bytes > free:
        raise StudyError(f"{study.path}: field '{size.largest}': the study asks for {size.describe()}; {where} has "
                         f"{gib(free)} free: reduce {size.largest} or choose another --out")


def _os_failure(exc: OSError, store: Path) -> str:
    """One line for a failed write: what happened, what is kept, how to resume."""
    import errno
    import sqlite3

    what = f"{exc.filename}: {exc.strerror}" if exc.filename and exc.strerror else f"{type(exc).__name__}: {exc}"
    try:
        db = sqlite3.connect(f"file:{store}?mode=ro", uri=True)
        try:
            n = db.execute("SELECT COUNT(*) FROM evaluations").fetchone()[0]
        finally:
            db.close()
        kept = f"the {n} evaluations stored in {store} are kept"
    except sqlite3.Error:
        kept = f"no evaluation store is kept ({store} cannot be read)"
    fix = {errno.ENOSPC: "free disk space", errno.EDQUOT: "free disk space", errno.EROFS: "make the folder writable",
           errno.EACCES: "make the folder writable (or choose another --out)",
           errno.EPERM: "make the folder writable (or choose another --out)",
           errno.ENOENT: "check that the output folder exists"}.get(exc.errno or 0, "fix the cause")
    return f"cannot write the run's files: {what}; {kept}; {fix}, then rerun the same command to resume"


def _finish(result: "StudyResult", out: Path, args: argparse.Namespace, verb: str) -> int:
    """Write the report, print the run's line and its problems, choose the exit code."""
    import pandas as pd

    from ddgsa.execute.confirm import verdict_line
    from ddgsa.report.write import evaluation_line, problems, write_report

    files = write_report(result, out)
    bad = problems(result)
    for msg in result.provenance.get("implausible", []):
        print(f"ddgsa: warning: {msg}", file=sys.stderr)
    if not args.quiet:
        print(f"{result.study.name}: {evaluation_line(result.provenance)}; {verb} {plural(len(files), 'file')} "
              f"to {out}")
        if isinstance(result.confirmation, pd.DataFrame) and len(result.confirmation):
            print(f"{result.study.name}: {verdict_line(result.confirmation)} (confirmation.csv)")
    if bad:
        allowed = getattr(args, "allow_untrusted", False)
        print(f"ddgsa: {'warning' if allowed else 'error'}: " + "; ".join(bad)
              + ("" if allowed else f" (see {out / 'summary.md'}; --allow-untrusted exits 0)"), file=sys.stderr)
        return EXIT_OK if allowed else EXIT_UNTRUSTED
    return EXIT_OK


def _report(args: argparse.Namespace) -> int:
    import json

    from ddgsa.errors import StudyError
    from ddgsa.report.outdir import claim
    from ddgsa.execute.pipeline import execute
    from ddgsa.runner import EvaluationStore
    from ddgsa.study.spec import load_study

    folder = args.dir
    if not (folder / "study.yaml").exists() or not (folder / "evaluations.sqlite").exists():
        raise StudyError(f"{folder}: not a study output folder (needs study.yaml and evaluations.sqlite from ddgsa run)")
    study = load_study(folder / "study.yaml")
    with claim(folder, study.name):
        store = EvaluationStore(folder / "evaluations.sqlite")
        try:
            result = execute(study, store, quiet=True, evaluate=False)
        finally:
            store.close()
        old = folder / "provenance.json"
        if old.exists():                          # keep what the run measured; note the rebuild
            ran = json.loads(old.read_text())
            result.provenance.update({k: ran[k] for k in ("evaluations", "timings_s") if k in ran})
            result.provenance["report_rebuilt_from_store"] = True
        return _finish(result, folder, args, "rebuilt")


def _bench(args: argparse.Namespace) -> int:
    import json

    from ddgsa.bench.speed import format_speed, speed

    if args.what == "trust":
        from ddgsa.bench.calibration import OUT, bench, held_out, ranking

        seeds = 3 if args.quick else 20
        head = (held_out(args.out or OUT, seeds=seeds) if args.held_out
                else ranking(args.out or OUT, seeds=seeds) if args.ranking else bench(args.out or OUT, quick=args.quick))
        print(json.dumps(head, indent=2))
        return EXIT_OK
    if args.what == "accuracy":
        from ddgsa.bench.accuracy_cost import OUT as ACC_OUT, run

        kw = {"max_log2": 10, "seeds": (0, 1), "drive_train": False} if args.quick else {}
        for path in run(args.out or ACC_OUT, **kw):
            print(f"wrote {path}")
        return EXIT_OK
    if args.what == "indirect":
        from ddgsa.bench.speed import format_indirect_speed, indirect_speed

        res = indirect_speed()
        print(format_indirect_speed(res))
        if args.json:
            args.json.parent.mkdir(parents=True, exist_ok=True)
            args.json.write_text(json.dumps(res, indent=2))
        return EXIT_OK
    if args.what == "rig":
        from ddgsa.bench.rig import format_rig_speed, rig_speed
        from ddgsa.bench.rig_chart import format_speed_accuracy, speed_accuracy
        from ddgsa.bench.rig_chart import write as write_rig_chart

        out = args.out or Path("results") / "rig_speed"
        out.mkdir(parents=True, exist_ok=True)          # an unusable --out fails before minutes of runs, not after
        res = rig_speed(quick=args.quick)
        print(format_rig_speed(res))
        chart = speed_accuracy(quick=args.quick)
        print(format_speed_accuracy(chart))
        for path in write_rig_chart(chart, out):
            print(f"wrote {path}")
        res = {**res, "speed_accuracy": chart}
    elif args.what == "scaling":
        from ddgsa.bench.scaling import format_scaling, scaling

        res = scaling(args.out or Path("results") / "scaling", quick=args.quick)
        print(format_scaling(res))
    else:
        from ddgsa.bench.speed import PAPER_C

        res = speed(ref_seconds=args.ref_seconds, quick=args.quick,
                    study=None if args.no_study or not PAPER_C.exists() else PAPER_C)
        print(format_speed(res))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(res, indent=2))
    return EXIT_OK


def _print_models(only: str | None = None) -> None:
    """``ddgsa models [NAME]``: each model's fidelities, scene fields, parameters and outputs with
    units and meanings; an unknown NAME is refused with the known ones."""
    import dataclasses

    from ddgsa.errors import ModelError, unknown_name_message
    from ddgsa.models import MODELS, get

    if only is not None and only not in MODELS:
        raise ModelError(unknown_name_message("model", only, list(MODELS)))
    for name in sorted(MODELS) if only is None else [only]:
        model = get(name)
        print(f"{name}: fidelities {', '.join(model.fidelities)} (the first is the default)")
        units = getattr(model.scene_type, "units", {})
        fields = [f.name for f in dataclasses.fields(model.scene_type) if f.name != "seed"]
        print("scene fields (scenes:): " + ", ".join(f"{f} [{units.get(f) or '-'}]" for f in fields))
        print("parameters:")
        print(model.parameter_table().to_string(index=False, formatters={"nominal": "{:.4g}".format}))
        print("outputs (a value outside the plausible range is warned about):")
        print(model.output_table().to_string(index=False, formatters={"plausible_low": "{:.3g}".format,
                                                                      "plausible_high": "{:.3g}".format}))
        if model.signal_outputs:
            print("signal outputs (signals: in a study; vectors on a fixed grid):")
            for sig in model.signal_outputs:
                print(f"  {sig.name} [{sig.unit}] against {sig.axis} [{sig.axis_unit}]: {sig.description}")
        print(f"{model.options_note}\n" if model.options_note else "")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
