"""`python3 -m camopt.studies STUDY.toml --out DIR [--workers N | --scheduler tcp://HOST:PORT]`,
which `camopt study` runs. Exit codes as the camopt CLI: 0 ok, 2 usage, 3 input error."""

from __future__ import annotations

import argparse
import sys

from . import StudyInputError, study
from .pipeline import OK


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # usage errors exit 2, as the CLI's
        self.print_usage(sys.stderr)
        print(f"camopt study: {message}", file=sys.stderr)
        sys.exit(2)


def _progress_line(quiet: bool):
    if quiet or not sys.stderr.isatty():
        return None

    def show(done: int, total: int) -> None:
        print(f"\rstudy: {done}/{total} points", end="" if done < total else "\n", file=sys.stderr, flush=True)

    return show


def main(argv: list[str] | None = None) -> int:
    parser = _Parser(prog="camopt study", description="Run a design study: DOE or geometry optimisation "
                     "over design and constraint-set keys (docs/studies.md).")
    parser.add_argument("study_file", metavar="STUDY.toml")
    parser.add_argument("--out", required=True, metavar="DIR", help="folder for results.csv, pareto.csv, "
                        "main_effects.csv, study.json")
    parser.add_argument("--workers", type=int, metavar="N", help="local processes [count] (default: all cores)")
    parser.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="run the points on this Dask scheduler's workers")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    args = parser.parse_args(argv)
    if args.workers is not None and args.scheduler is not None:
        parser.error("--workers and --scheduler exclude each other")
    try:
        result = study(args.study_file, out=args.out, workers=args.workers, scheduler=args.scheduler,
                       progress=_progress_line(args.quiet))
    except StudyInputError as e:
        print(f"camopt: input error: {e}", file=sys.stderr)
        return 3
    except KeyboardInterrupt:
        print("camopt: interrupted; the output folder is unchanged", file=sys.stderr)
        return 130
    if not args.quiet:
        ok = sum(1 for r in result.points if r.status == OK)
        line = (f"study: {len(result.points)} points ({ok} ok, {len(result.points) - ok} failed) in "
                f"{result.seconds:.3g} s on {result.executor}")
        if result.spec.pareto:
            line += f"; Pareto set {len(result.pareto)} points"
        if result.spec.optimisation:
            best = result.best
            line += (f"; best {result.spec.optimisation.objective} "
                     f"{best.responses[[r.name for r in result.spec.responses].index(result.spec.optimisation.objective)]!r}"
                     f" at point {best.index} ({result.stop_reason})" if best else "; no feasible point")
        print(line + f" -> {args.out}/results.csv, pareto.csv, main_effects.csv, study.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
