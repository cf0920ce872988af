"""The ``ddgsa`` command: ``run``, ``validate``, ``models``, ``report``, ``bench``, ``modes``.

Exit codes: 0 success, 1 a failure while running, 2 invalid input. Errors print one clear
message and no traceback (``--verbose`` adds it).
"""

from __future__ import annotations

import argparse
import logging
import shutil
import sys
import traceback
from pathlib import Path

from ddgsa.errors import DdgsaError

EXIT_OK, EXIT_FAILURE, EXIT_INPUT = 0, 1, 2


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="ddgsa", description="Global sensitivity analysis of wind-turbine drive trains.")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar, only errors")
    p.add_argument("-v", "--verbose", action="store_true", help="tracebacks and debug messages")
    sub = p.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a study and write its report")
    run.add_argument("study", type=Path)
    run.add_argument("--out", type=Path, help="output folder (default results/<study name>)")
    run.add_argument("--jobs", type=int, help="parallel workers (default from the study, else 1)")
    run.add_argument("--backend", choices=["loky", "dask"], help="joblib loky (default) or a Dask cluster")
    run.add_argument("--address", help="Dask scheduler HOST:PORT (default: a LocalCluster)")
    val = sub.add_parser("validate", help="check a study file; exit 0 or 2")
    val.add_argument("study", type=Path)
    sub.add_parser("models", help="list models, fidelities, parameters and outputs")
    rep = sub.add_parser("report", help="rebuild tables and plots from a run's stored evaluations")
    rep.add_argument("dir", type=Path)
    ben = sub.add_parser("bench", help="speed of each fidelity (default), or accuracy against cost of each method")
    ben.add_argument("what", nargs="?", choices=["speed", "accuracy", "indirect"], default="speed",
                     help="speed: fidelities against the solve_ivp reference; accuracy: index error against "
                          "evaluations and wall time, written to --out; indirect: the indirect drive's "
                          "fidelities against their references")
    ben.add_argument("--out", type=Path, default=Path("results") / "accuracy_cost",
                     help="folder for the accuracy benchmark's CSVs and charts")
    ben.add_argument("--quick", action="store_true",
                     help="accuracy: Saltelli/RBD-FAST up to 2^10 with 2 seeds, no drive-train part (a minute)")
    ben.add_argument("--json", type=Path, help="also write the figures to this JSON file")
    ben.add_argument("--ref-seconds", type=float, default=20.0, help="scene seconds the slow reference integrates")
    ben.add_argument("--no-quickstart", action="store_true", help="skip timing the quickstart study")
    mod = sub.add_parser("modes", help="natural frequencies of a model or a study's model (CSV + PNG); "
                                       "--campbell: against rotor speed")
    mod.add_argument("target", help="a model name (see ddgsa models) or a study YAML file")
    mod.add_argument("--campbell", action="store_true", help="modes against rotor speed with order lines")
    mod.add_argument("--max-rpm", type=float, default=20.0, help="highest rotor speed of the Campbell diagram [rpm]")
    mod.add_argument("--points", type=int, default=11, help="rotor speeds from 0 to --max-rpm")
    mod.add_argument("--orders", type=float, nargs="+", default=[1.0, 3.0], help="excitation orders (1P, 3P ...)")
    mod.add_argument("--out", type=Path, help="output folder (default results/modes_<name>)")
    return p


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script."""
    args = _parser().parse_args(argv)
    logging.basicConfig(level=logging.DEBUG if args.verbose else logging.WARNING, format="%(message)s")
    try:
        return _dispatch(args)
    except DdgsaError as exc:
        if args.verbose:
            traceback.print_exc()
        print(f"ddgsa: error: {exc}", file=sys.stderr)
        return EXIT_INPUT if isinstance(exc, ValueError) else EXIT_FAILURE
    except KeyboardInterrupt:
        print("ddgsa: interrupted; finished batches are stored, rerun to resume", file=sys.stderr)
        return EXIT_FAILURE
    except Exception as exc:  # noqa: BLE001 -- the CLI reports, it does not crash
        if args.verbose:
            traceback.print_exc()
        print(f"ddgsa: failed: {type(exc).__name__}: {exc} (rerun with --verbose for the traceback)",
              file=sys.stderr)
        return EXIT_FAILURE


def _dispatch(args: argparse.Namespace) -> int:
    from ddgsa.study import load_study

    if args.command == "validate":
        study = load_study(args.study)
        print(f"{args.study}: valid ({study.spec.kind} study '{study.name}', model {study.spec.model.name}, "
              f"{len(study.spec.parameters)} parameters, {len(study.spec.scenes.grid())} scenes x "
              f"{study.spec.scenes.realisations} realisations)")
        return EXIT_OK
    if args.command == "models":
        _print_models()
        return EXIT_OK
    if args.command == "run":
        study = load_study(args.study)
        if args.jobs is not None and args.jobs < 1:
            print("ddgsa: error: --jobs must be >= 1", file=sys.stderr)
            return EXIT_INPUT
        return _run(study, args)
    if args.command == "report":
        return _report(args.dir, args.quiet)
    if args.command == "bench":
        return _bench(args)
    if args.command == "modes":
        return _modes(args)
    return EXIT_INPUT  # pragma: no cover (argparse requires a command)


def _modes(args: argparse.Namespace) -> int:
    """``ddgsa modes``: the model's mode table, or its Campbell diagram (from ``model.campbell`` or
    from ``model.modes(rotor_speed=...)`` at each speed), as CSV and PNG."""
    import inspect

    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    from ddgsa import models
    from ddgsa.errors import ModelError
    from ddgsa.mbs.campbell import campbell_from_tables
    from ddgsa.mbs.modal import plot_modes
    from ddgsa.study import load_study

    target = Path(args.target)
    if target.suffix in (".yaml", ".yml") or target.exists():
        study = load_study(target)
        model, name = study.make_model(), study.name
    else:
        model, name = models.get(args.target), args.target
    out = args.out or Path("results") / f"modes_{name}"
    out.mkdir(parents=True, exist_ok=True)
    if not args.campbell:
        table = model.modes()
        table.to_csv(out / "modes.csv", index=False)
        plot_modes(table).figure.savefig(out / "modes.png", dpi=120, bbox_inches="tight")
        if not args.quiet:
            print(table[["frequency_hz", "damping_ratio", "label"]].to_string(index=False))
            print(f"wrote {out / 'modes.csv'} and {out / 'modes.png'}")
        return EXIT_OK
    if args.points < 2 or args.max_rpm <= 0:
        raise ModelError(f"--points ({args.points}) must be >= 2 and --max-rpm ({args.max_rpm}) > 0")
    speeds = np.linspace(0.0, args.max_rpm * np.pi / 30.0, args.points)
    if hasattr(model, "campbell"):
        diagram = model.campbell(speeds=speeds, orders=args.orders)
    elif "rotor_speed" in inspect.signature(model.modes).parameters:
        diagram = campbell_from_tables({s: model.modes(rotor_speed=s) for s in speeds}, args.orders)
    else:
        raise ModelError(f"model {name!r} has no rotor speed to sweep: no Campbell diagram (ddgsa modes {args.target} "
                         "without --campbell gives its modes)")
    diagram.to_frame().to_csv(out / "campbell.csv", index=False)
    diagram.plot().figure.savefig(out / "campbell.png", dpi=120, bbox_inches="tight")
    if not args.quiet:
        for order in args.orders:
            cross = diagram.crossings(order)
            for _, row in cross.iterrows():
                print(f"{order:g}P crosses mode {row['mode']} at {row['speed_rpm']:.2f} rpm ({row['frequency_hz']:.3g} Hz)")
        print(f"wrote {out / 'campbell.csv'} and {out / 'campbell.png'}")
    return EXIT_OK


def _run(study, args: argparse.Namespace) -> int:  # noqa: ANN001
    from ddgsa.pipeline import default_out, execute
    from ddgsa.report import write_report
    from ddgsa.runner import EvaluationStore

    out = args.out or default_out(study)
    out.mkdir(parents=True, exist_ok=True)
    if study.path is not None and study.path.resolve() != (out / "study.yaml").resolve():
        shutil.copyfile(study.path, out / "study.yaml")
    store = EvaluationStore(out / "evaluations.sqlite")
    try:
        result = execute(study, store, jobs=args.jobs, backend=args.backend, address=args.address, quiet=args.quiet)
    finally:
        store.close()
    files = write_report(result, out)
    ev = result.provenance["evaluations"]
    if not args.quiet:
        print(f"{study.name}: {ev['evaluated']} model runs ({ev['cached']} cached, {ev['failed']} failed) in "
              f"{result.provenance['timings_s']['total']:.1f} s; wrote {len(files)} files to {out}")
    return EXIT_OK


def _report(folder: Path, quiet: bool) -> int:
    from ddgsa.errors import StudyError
    from ddgsa.pipeline import execute
    from ddgsa.report import write_report
    from ddgsa.runner import EvaluationStore
    from ddgsa.study import load_study

    if not (folder / "study.yaml").exists() or not (folder / "evaluations.sqlite").exists():
        raise StudyError(f"{folder}: not a study output folder (needs study.yaml and evaluations.sqlite from ddgsa run)")
    study = load_study(folder / "study.yaml")
    store = EvaluationStore(folder / "evaluations.sqlite")
    try:
        result = execute(study, store, quiet=True, evaluate=False)
    finally:
        store.close()
    old = folder / "provenance.json"
    if old.exists():                          # keep what the run measured; note the rebuild
        import json

        ran = json.loads(old.read_text())
        result.provenance.update({k: ran[k] for k in ("evaluations", "timings_s") if k in ran})
        result.provenance["report_rebuilt_from_store"] = True
    files = write_report(result, folder)
    if not quiet:
        print(f"{study.name}: rebuilt {len(files)} files in {folder} from stored evaluations")
    return EXIT_OK


def _bench(args: argparse.Namespace) -> int:
    import json

    from ddgsa.bench import format_speed, speed

    if args.what == "accuracy":
        from ddgsa.accuracy_cost import run

        kw = {"max_log2": 10, "seeds": (0, 1), "drive_train": False} if args.quick else {}
        for path in run(args.out, **kw):
            print(f"wrote {path}")
        return EXIT_OK
    if args.what == "indirect":
        from ddgsa.bench import format_indirect_speed, indirect_speed

        res = indirect_speed()
        print(format_indirect_speed(res))
        if args.json:
            args.json.parent.mkdir(parents=True, exist_ok=True)
            args.json.write_text(json.dumps(res, indent=2))
        return EXIT_OK
    quick = None if args.no_quickstart else Path(__file__).resolve().parents[2] / "studies" / "quickstart.yaml"
    res = speed(ref_seconds=args.ref_seconds, quickstart=quick if quick is not None and quick.exists() else None)
    print(format_speed(res))
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(res, indent=2))
    return EXIT_OK


def _print_models() -> None:
    from ddgsa.models import MODELS, get

    for name in sorted(MODELS):
        model = get(name)
        print(f"{name}: fidelities {', '.join(model.fidelities)}")
        print(model.parameter_table().to_string(index=False, formatters={"nominal": "{:.4g}".format}))
        print(f"outputs: {', '.join(model.outputs)}")
        print(f"{model.options_note}\n" if model.options_note else "")


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
