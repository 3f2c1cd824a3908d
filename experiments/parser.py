"""The ``animat`` command line: its commands, their options and help (:func:`make_parser`).

It imports only the standard library (neither the simulator nor the learners, which the demo's
and the runs' modules pull in), so that ``animat --help`` and a mistyped option answer at once;
:mod:`animat.experiments.cli` runs the command parsed.
"""

from __future__ import annotations

import argparse
from pathlib import Path

EXAMPLES = """examples:
  animat run quickstart                                    # a shipped config, from anywhere
  animat run configs/quickstart.yaml                       # one run, folder under runs/
  animat run configs/fish_swim/ppo.yaml --set seed=3 --set budget.env_steps=20000 --out runs/try
  animat run --resume runs/try                             # continue a killed or failed run
  animat sweep configs/fish_swim/cmaes.yaml --seeds 0-4 --jobs 2 --out runs/cmaes
  animat compare runs/cmaes runs/ppo --metric eval/speed_bl_per_s -o docs/report.md
  animat eval runs/try --episodes 4 --video videos/        # re-score and film a finished run
  animat tune configs/fish_swim/tune_annealing.yaml --trials 12 --out runs/tune/annealing
  animat list                                              # envs, learners, shipped configs
  animat --import my_animals run eel.yaml                  # your module's registrations too
"""


def _version() -> str:
    from importlib import metadata

    try:
        return metadata.version("artificial-animals")
    except metadata.PackageNotFoundError:
        return "unknown (not installed)"


def _add_overrides(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--set", dest="overrides", action="append", default=[],
                        metavar="KEY.PATH=VALUE",
                        help="override a config field (value read as YAML); repeatable, e.g. "
                             "--set seed=3 --set learner.params.chains=32")


def make_parser() -> argparse.ArgumentParser:
    """``animat``'s parser: ``--version``, ``--debug`` and a subcommand each (``command``)."""
    parser = argparse.ArgumentParser(
        prog="animat", description="artificial-animals: run, sweep, compare and re-score "
        "experiments on the artificial fish", epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version",
                        version=f"animat (artificial-animals) {_version()}")
    parser.add_argument("--import", dest="imports", action="append", default=[],
                        metavar="MODULE",
                        help="import your module first, so the bodies, tasks, sensors, env ids "
                             "and learners it registers are known; repeatable, e.g. animat "
                             "--import my_animals run eel.yaml")
    parser.add_argument("--debug", action="store_true",
                        help="on a failure, the full traceback instead of one line")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    run = sub.add_parser("run", help="run one experiment (or --resume one)",
                         description="Run one experiment from a YAML config into a new run "
                         "folder, or continue an unfinished one.")
    run.add_argument("config", nargs="?", help="YAML config, or a shipped config's name "
                     "(animat list); not with --resume")
    _add_overrides(run)
    run.add_argument("--out", type=Path, help="the run folder, exactly (default: "
                     "runs/<env>/<learner>/seed<k>-<time>/); never overwritten")
    run.add_argument("--resume", type=Path, metavar="DIR",
                     help="continue the unfinished run in DIR with its own config.yaml")
    run.add_argument("--trust-pickles", action="store_true",
                     help="--resume: also from an older version's pickled checkpoint (loading "
                          "it runs any code its writer put in it: only for folders you trust)")
    run.add_argument("--threads", type=int, metavar="N",
                     help="Numba threads for the run (default: every CPU this process may use)")
    run.add_argument("--quiet", action="store_true", help="no progress bar")
    run.add_argument("--force", action="store_true",
                     help="let learner.params.output replace a file that exists (a run never "
                          "overwrites one otherwise)")
    sweep = sub.add_parser("sweep", help="one run per seed",
                           description="One run folder per seed, run here (one after another "
                           "or --jobs at once) or as Ray tasks; ends with a table.")
    sweep.add_argument("config", help="YAML config, or a shipped config's name")
    sweep.add_argument("--seeds", required=True, help="e.g. 0-4 or 1,3,5")
    _add_overrides(sweep)
    sweep.add_argument("--executor", choices=("local", "ray"), default="local",
                       help="local processes (default) or Ray tasks of one CPU each")
    sweep.add_argument("--jobs", type=int, default=1,
                       help="local: runs at once, sharing the CPUs out (default 1)")
    sweep.add_argument("--address", help="ray: an existing cluster's address (default: start "
                       "a local one)")
    sweep.add_argument("--out", type=Path, help="parent folder of the run folders "
                       "(default: runs/)")
    compare = sub.add_parser("compare", help="compare runs (TensorBoard events)",
                             description="A table of final and best values per learner "
                             "(label), with the interquartile mean and its stratified-bootstrap "
                             "interval; a plot of the curves against env steps and a "
                             "performance profile. Runs of one setting (env, water, "
                             "integrator) only.")
    compare.add_argument("paths", nargs="+", help="run folders, or parents of run folders")
    compare.add_argument("--metric", help="the tag compared (default: the runs' configs' "
                         "eval.metric)")
    compare.add_argument("--threshold", type=float, help="report env steps to reach it")
    compare.add_argument("-o", "--output", type=Path, help="Markdown report (+ .png plot)")
    tune = sub.add_parser("tune", help="hyperparameter search (Optuna) over tune.space",
                          description="Optuna over the config's tune.space: every trial a run "
                          "folder under OUT, the study in OUT/journal.log (run again with the "
                          "same --out to continue), the best config in OUT/best.yaml.")
    tune.add_argument("config", help="YAML config with a tune.space, or a shipped one's name")
    tune.add_argument("--trials", type=int, required=True, help="finished trials wanted")
    _add_overrides(tune)
    tune.add_argument("--out", type=Path, help="the study's folder (default: runs/tune/...)")
    tune.add_argument("--storage", metavar="URL", help="an RDB URL for the study (e.g. "
                      "postgresql://host/db, for workers on several machines; default: a "
                      "journal file in --out)")
    tune.add_argument("--study", metavar="NAME", help="the study's name in its storage "
                      "(default: 'tune' in --out's own storage; with --storage, the config "
                      "file's name and a digest of it and the --set values, so workers given "
                      "the same command join one study)")
    tune.add_argument("--workers", type=int, default=1, help="trials at once, each worker "
                      "a process here (sharing the CPUs out) or, with --executor ray, a Ray "
                      "task of one CPU; all on the one study (default 1)")
    tune.add_argument("--executor", choices=("local", "ray"), default="local",
                      help="local processes (default) or Ray tasks")
    tune.add_argument("--address", help="ray: an existing cluster's address (default: start "
                      "a local one); the study's storage must reach every node (--storage)")
    evaluation = sub.add_parser("eval", help="play a finished run's agent over start states",
                                description="Load a finished run's agent, play it on seeded "
                                "start states, print its metric and write eval.json.")
    evaluation.add_argument("run_dir", type=Path, help="a finished run folder")
    evaluation.add_argument("--episodes", type=int,
                            help="start states it never learned from, seeds from 1,000,000 + "
                                 "the run's seed on (default: as many as the run's own scores "
                                 "are over)")
    evaluation.add_argument("--seeds", help="these seeds instead, e.g. 0-4 or 1,3,5 (the run's own "
                                 "start states: its seed on)")
    evaluation.add_argument("--video", type=Path, metavar="DIR",
                            help="film every episode into DIR (mp4, Gymnasium's RecordVideo)")
    evaluation.add_argument("--trust-pickles", action="store_true",
                            help="also load an older version's pickled checkpoint (it runs "
                                 "any code its writer put in it: only for folders you trust)")
    evaluation.add_argument("--refine", type=int, default=1, metavar="K",
                            help="play at the physics step divided by K (frame_skip times K; "
                                 "the env step unchanged): is the figure the solver's?")
    evaluation.add_argument("--point-start", action="store_true",
                            help="play from the task's documented start (start_spread=point and "
                                 "no reset noise: one episode unless told) instead of its "
                                 "spread; writes "
                                 "eval_point_start.json")
    bench = sub.add_parser("bench", help="simulator benchmark against Swimmer-v5")
    bench.add_argument("--seconds", type=float, default=6.0, help="wall seconds measured")
    bench.add_argument("--num-envs", type=int, default=256, help="the batch's size")
    bench.add_argument("--breakdown", action="store_true",
                       help="where an integration step's time goes, per force term")
    bench.add_argument("--learners", action="store_true",
                       help="annealing, CMA-ES and PPO's env steps/s as they learn, against "
                            "the native batch they step, in the same rounds")
    stunts = sub.add_parser("stunt-figures", help="the paper's Figs. 10, 11 and a leap video "
                            "from finished dolphin macro runs")
    stunts.add_argument("--out", type=Path, required=True, help="folder for the files")
    stunts.add_argument("--leap", type=Path, required=True, help="a finished leap macro run")
    for name in ("nose-ball", "tail-ball", "somersault", "belly-flop"):
        stunts.add_argument(f"--{name}", type=Path, help=f"a finished {name} run (macro or PPO)")
    figures = sub.add_parser("figures", help="the paper's Figs. 5, 7, 8 from a pursuit")
    figures.add_argument("--out", type=Path, required=True, help="folder for the PNG files")
    figures.add_argument("--seed", type=int, default=0, help="the pursuit's seed")
    figures.add_argument("--frames", type=int, default=400, help="frames of the pursuit")
    demo_arguments(sub.add_parser("demo", help="swim the fish with its hand-designed motor "
                                  "controllers and print St, stride, turns, fins"))
    world_bench = sub.add_parser("world-bench", help="the 10-fish world's env steps/s, "
                                 "without and with one fish's eyes")
    world_bench.add_argument("--seconds", type=float, default=3.0,
                             help="wall seconds per measurement (3 interleaved rounds)")
    world_bench.add_argument("--fish", metavar="N,N,...",
                             help="how the cost grows instead: worlds of these many fish at "
                                  "the paper's density, e.g. 10,100,1000")
    world_bench.add_argument("--plot", type=Path, metavar="FILE",
                             help="--fish: a log-log plot of the cost (PNG)")
    world_video = sub.add_parser("world-video", help="a video of the living world")
    world_video.add_argument("--out", type=Path, required=True, help="the mp4 file")
    world_video.add_argument("--seconds", type=float, default=60.0, help="simulated seconds")
    world_video.add_argument("--seed", type=int, default=0, help="the world's seed")
    world_video.add_argument("--vision", action="store_true",
                             help="the shark hunts by its eyes and active vision")
    sub.add_parser("list", help="registered envs, learners and shipped configs")
    return parser


def demo_arguments(parser: argparse.ArgumentParser) -> None:
    """The demo's options (its own command line and ``animat demo``)."""
    parser.add_argument("--seconds", type=float, default=10.0, help="simulated seconds of the swim")
    parser.add_argument("--video", default=None, help="folder for an mp4 of the swim")
    parser.add_argument("--model-sweep", action="store_true",
                        help="print St and stride across force models and swim-MC gains")
