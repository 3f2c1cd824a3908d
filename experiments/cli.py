"""The ``animat`` command (also ``python -m animat.experiments``).

    animat [--debug] [--import MODULE ...] COMMAND ...
    animat run CONFIG [--set key.path=value ...] [--out DIR] [--threads N] [--force]
    animat run --resume DIR [--threads N]
    animat sweep CONFIG --seeds 0-4 [--set ...] [--executor local|ray] [--jobs N]
                 [--address ADDR] [--out PARENT]
    animat compare RUN_DIR_OR_PARENT ... [--metric eval/return] [--threshold X] [-o REPORT]
    animat eval RUN_DIR [--episodes N] [--seeds 0-3] [--video DIR]
    animat tune CONFIG --trials N [--set ...] [--out DIR] [--storage URL] [--study NAME]
                [--workers N] [--executor local|ray] [--address ADDR]
    animat bench [--seconds S] [--breakdown | --learners]
    animat demo [--seconds S] [--video DIR] [--model-sweep]
    animat figures --out DIR [--seed S] [--frames N]
    animat stunt-figures --out DIR --leap RUN [--nose-ball RUN] [--tail-ball RUN]
                         [--somersault RUN] [--belly-flop RUN]
    animat world-bench [--seconds S] [--fish 10,100,1000 [--plot FILE]]
    animat list
    animat --version

CONFIG is a YAML file, or a shipped config by name (``quickstart``, ``fish_swim/tune_ppo``;
``animat list`` names them all), from any directory. A bad config or override stops before any
work with one line naming the file, the field path and what is wrong, and exit status 2; so
does a file given that will not be read (a link in a run folder, a FIFO, a device, one too
large: ``UnsafeFile``; one truncated or corrupt: ``CorruptFile``). Any other failure is one
line too, exit status 1 (a run's traceback is in its folder's
``error.log``; ``--debug`` shows it instead). The options and their help are
:mod:`animat.experiments.parser`'s; this module runs the commands.
"""

from __future__ import annotations

import json
import os
import sys
import threading
from contextlib import contextmanager
from pathlib import Path

from animat.learners.ppo.threads import load_torch_first
from animat.learners.storage.files import CorruptFile, UnsafeFile

from .launch.config import ConfigError, load_config, load_run_config
from .launch.folders import create_run, one_line
from .launch.lock import RunError
from .launch.plugins import ImportRefused, import_modules
from .launch.shipped import describe_config, find_config, shipped_configs
from .parser import make_parser


def _progress(args, config, label: str = ""):
    """The run's progress (a bar on a terminal, log lines elsewhere), after a notice if the
    physics kernels are about to compile; None with --quiet or ``logging.progress: false``."""
    from .launch.progress import ProgressSink, compile_notice

    if getattr(args, "quiet", False) or not config.logging.progress:
        return None
    compile_notice()
    return ProgressSink.for_output(config.budget.env_steps, config.eval.metric, label)


def _config_path(name: str) -> Path:
    """The config file a user names (a path, or a shipped config's name); RunError if none.
    A path that is there but no regular file (a device, a FIFO) is left to the config's
    reader, which refuses it naming what it is."""
    path = find_config(name)
    if not os.path.lexists(path):
        raise RunError(f"{name}: no such file, nor a shipped config (animat list names them)")
    return path


def _forced(config_path: Path, overrides: list[str]) -> list[str]:
    """``--force``: the overrides that let the config's learner.params.output replace a file;
    RunError if the config writes nothing outside its run folder."""
    config = load_config(config_path, overrides, build=False)
    if not config.learner.params.get("output"):
        raise RunError("--force: this config writes nothing outside its run folder (no "
                       "learner.params.output)")
    return [*overrides, "learner.params.force=true"]


def _single_output(config, runs: int, what: str) -> None:
    """RunError if ``runs`` runs of ``what`` would all write one learner.params.output."""
    if runs > 1 and config.learner.params.get("output"):
        raise RunError(f"learner.params.output: the {runs} runs of {what} would all write "
                       f"{config.learner.params['output']}; give an output to one animat run")


def cmd_run(args) -> int:
    from .launch.execute import execute, resume

    if args.threads is not None and args.threads < 1:
        raise RunError(f"--threads must be at least 1, got {args.threads}")
    if args.resume:
        folder = args.resume
        ignored = ([f"CONFIG {args.config}"] if args.config else []) + (
            [f"--set {o}" for o in args.overrides] + ([f"--out {args.out}"] if args.out else [])
            + (["--force"] if args.force else []))
        if ignored:
            raise RunError(f"--resume continues {folder} with its own config.yaml; drop "
                           f"{', '.join(ignored)} (they would be ignored)")
        if not (folder / "config.yaml").exists():
            raise RunError(f"{folder}: no config.yaml: not a run folder")
        config = load_run_config(folder)  # built by the run
        result = resume(folder, _progress(args, config), args.threads, args.trust_pickles)
    else:
        if not args.config:
            raise RunError("give a CONFIG to run, or --resume DIR")
        if args.trust_pickles:
            raise RunError("--trust-pickles is for --resume DIR (a new run loads no checkpoint)")
        path = _config_path(args.config)
        overrides = _forced(path, args.overrides) if args.force else args.overrides
        config = load_config(path, overrides)
        folder = create_run(config, args.out, ["animat", *args.argv])
        print(f"run folder: {folder}")
        result = execute(folder, _progress(args, config), args.threads, checked=True)
    print(json.dumps({k: result[k] for k in ("status", "env_steps", "wall_seconds", "metrics")}))
    return 0


def cmd_sweep(args) -> int:
    from .executors import run_ray
    from .sweep import parse_seeds, prepare, run_local, summary_table

    try:
        seeds = parse_seeds(args.seeds)
    except ValueError as error:
        raise RunError(str(error)) from None
    config = load_config(_config_path(args.config), args.overrides)
    _single_output(config, len(seeds), "the sweep")
    folders = prepare(config, seeds, args.out, ["animat", *args.argv])
    if args.executor == "ray":
        results = run_ray(folders, args.address)
    else:
        results = run_local(folders, args.jobs, progress=lambda folder: _progress(args, config,
                                                                           folder.name))
    print(summary_table(folders, results, config.eval.metric))
    return 0 if all(r["status"] == "done" for r in results) else 1


def cmd_tune(args) -> int:
    from .tune import table, tune

    if args.trials < 1:
        raise RunError(f"--trials must be at least 1, got {args.trials}")
    if args.study is not None and not args.study.strip():
        raise RunError("--study must name the study, got an empty name")
    path = _config_path(args.config)
    _single_output(load_config(path, args.overrides, build=False), args.trials, "the study")
    if args.workers < 1:
        raise RunError(f"--workers must be at least 1, got {args.workers}")
    if args.address and args.executor != "ray":
        raise RunError("--address is the Ray cluster's: give it with --executor ray")
    summary = tune(path, args.trials, args.out, args.overrides, args.storage, args.study,
                   args.workers, args.executor, args.address)
    print(table(summary))
    return 0 if summary["best"] is not None else 1


def cmd_eval(args) -> int:
    from .evaluate import evaluate, report, result_name
    from .sweep import parse_seeds

    if args.episodes is not None and args.episodes < 1:
        raise RunError(f"--episodes must be at least 1, got {args.episodes}")
    try:
        seeds = parse_seeds(args.seeds) if args.seeds else None
    except ValueError as error:
        raise RunError(str(error)) from None
    result = evaluate(args.run_dir, seeds, args.episodes, args.video, args.refine,
                      args.trust_pickles, args.point_start)
    print(report(result))
    if result.get("shipped"):
        print(result["shipped"])
        return 0
    if result.get("not_written"):  # scored, but the folder would not take the file
        print(f"animat: error: not written: {result['not_written']}", file=sys.stderr)
        return 1
    print(f"written: {args.run_dir / result_name(args.refine, args.point_start)}" + (
        f"; videos in {args.video}" if args.video else ""))
    return 0


def cmd_compare(args) -> int:
    from .compare import compare

    text, image = compare(args.paths, args.metric, args.threshold, args.output)
    print(text)
    if args.output:
        print(f"report: {args.output}; plot: {image}")
    return 0


def cmd_list(args) -> int:
    import gymnasium as gym

    import animat  # noqa: F401  (registers Animat/*)
    from animat.learners.registry import LEARNERS

    envs = sorted(k for k in gym.registry if k.startswith("Animat/"))
    configs = shipped_configs()
    print(f"envs ({len(envs)}):\n  " + "\n  ".join(envs))
    print(f"learners ({len(LEARNERS)}): " + ", ".join(sorted(LEARNERS)))
    width = max((len(name) for name in configs), default=0)
    print(f"shipped configs ({len(configs)}; animat run NAME):\n  "
          + ("\n  ".join(f"{name:<{width}}  {describe_config(name)}" for name in configs)
             if configs else "(none)"))
    return 0 if envs and configs else 1


def cmd_stunt_figures(args) -> int:
    from .figures.stunts import make_stunt_figures

    result = make_stunt_figures(args.out, args.leap, args.nose_ball, args.tail_ball,
                                args.somersault, args.belly_flop)
    print(f"figures in {args.out}: " + ", ".join(f"{k} {v:.3g}" for k, v in result.items()))
    return 0


def cmd_figures(args) -> int:
    from .figures.vision import make_figures

    if args.frames < 8:
        raise RunError(f"--frames must be at least 8, got {args.frames}")
    result = make_figures(args.out, args.seed, args.frames)
    print(f"figures in {args.out}: " + ", ".join(f"{k} {v:.3g}" for k, v in result.items()))
    return 0


def cmd_demo(args) -> int:
    from .demo import run

    run(args)
    return 0


def cmd_bench(args) -> int:
    from .bench.physics import report, report_breakdown, run

    if not args.seconds > 0:
        raise RunError(f"--seconds must be > 0, got {args.seconds}")
    if args.breakdown and args.learners:
        raise RunError("--breakdown and --learners are two benchmarks: give one")
    if args.breakdown:
        print(report_breakdown())
        return 0
    if args.learners:
        from .bench import learners

        print(learners.report(learners.run(args.seconds)))
        return 0
    print(report(run(args.seconds, args.num_envs), args.num_envs))
    return 0


def cmd_world_bench(args) -> int:
    from .bench.world import plot_sizes, report, report_sizes, run, run_sizes
    from .sweep import parse_seeds

    if not args.seconds > 0:
        raise RunError(f"--seconds must be > 0, got {args.seconds}")
    if args.fish is None:
        if args.plot:
            raise RunError("--plot is the growth plot of --fish: give --fish too")
        print(report(run(args.seconds)))
        return 0
    try:
        sizes = parse_seeds(args.fish)
    except ValueError:
        raise RunError(f"--fish {args.fish!r}: give fish counts like 10,100,1000") from None
    if not 1 <= len(sizes) <= 8 or min(sizes) < 1 or max(sizes) > 3000:
        raise RunError(f"--fish {args.fish!r}: up to 8 counts, each in [1, 3000]")
    result = run_sizes(sizes, args.seconds)
    print(report_sizes(result))
    if args.plot:
        plot_sizes(result, args.plot)
        print(f"plot: {args.plot}")
    return 0


def cmd_world_video(args) -> int:
    from .figures.world_video import world_video

    if not args.seconds > 0:
        raise RunError(f"--seconds must be > 0, got {args.seconds}")
    totals = world_video(args.out, args.seconds, args.seed, args.vision)
    print(f"video: {args.out}; " + ", ".join(f"{k} {v:g}" for k, v in totals.items()))
    return 0


@contextmanager
def _thread_errors(debug: bool):
    """Collect the exceptions of background threads (TensorBoard's writer on a full disk)
    into the yielded list instead of printing their tracebacks (``debug``: printed as
    usual); such a thread's failure also reaches the run itself, which says it in one line."""
    failed: list[BaseException] = []
    previous = threading.excepthook
    if not debug:
        threading.excepthook = lambda hook: failed.append(hook.exc_value)
    try:
        yield failed
    finally:
        threading.excepthook = previous


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    args = make_parser().parse_args(argv)
    args.argv = argv  # recorded in each run folder's command.txt
    with _thread_errors(args.debug) as failed:
        code = _dispatch(args)
    if code == 0 and failed:  # the command ended well, but a thread of it did not
        print(f"animat: error: in a background thread: {one_line(failed[0])}", file=sys.stderr)
        return 1
    return code


LEARNING = {"run", "sweep", "eval", "tune"}  # the commands that may run a torch learner


def _dispatch(args) -> int:
    """Run the command; a failure is one line on stderr and its exit status (2: what the user
    gave, a config or a file that will not be read, unless a run recorded it as its failure;
    1: while working; 130: interrupted)."""
    handlers = {"run": cmd_run, "sweep": cmd_sweep, "compare": cmd_compare, "list": cmd_list,
                "bench": cmd_bench, "demo": cmd_demo, "figures": cmd_figures,
                "stunt-figures": cmd_stunt_figures,
                "eval": cmd_eval, "tune": cmd_tune, "world-bench": cmd_world_bench,
                "world-video": cmd_world_video}
    try:
        if args.command in LEARNING or getattr(args, "learners", False):
            load_torch_first()  # before any env step starts Numba's threads
        import_modules(args.imports)
        return handlers[args.command](args)
    except KeyboardInterrupt:
        if args.debug:
            raise
        print("animat: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # the reader went away (animat list | head): nothing to say
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())  # no flush error at exit
        return 141
    except Exception as error:
        if args.debug:
            raise
        folder = getattr(error, "run_folder", None)
        if folder is None and isinstance(error, ConfigError | RunError | FileNotFoundError
                                         | UnsafeFile | CorruptFile | ImportRefused):
            print(f"animat: error: {error}", file=sys.stderr)  # what the user gave
            return 2
        log = getattr(error, "error_log", None)  # None where the disk would not take it
        where = (f" (traceback in {log})" if log else " (animat --debug ... shows the traceback)")
        print(f"animat: error: {one_line(error)}{where}", file=sys.stderr)  # while working
        return 1

if __name__ == "__main__":
    sys.exit(main())
