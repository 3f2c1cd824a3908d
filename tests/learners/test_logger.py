"""The run folder's sinks write each (tag, step) once: a resumed run, which logs again what it
had logged between its last checkpoint and the kill, adds no duplicate rows or events, and a row
a kill cut short is dropped."""

import csv

import pytest

from animat.learners.logger import CsvSink, Logger, TensorBoardSink, _events_held


def _rows(path):
    with path.open(newline="") as file:
        return [tuple(row) for row in csv.reader(file)]


def test_a_reopened_csv_sink_writes_each_tag_and_step_once(tmp_path):
    path = tmp_path / "scalars.csv"
    first = Logger([CsvSink(path)])
    first.scalars({"eval/return": 1.5, "train/loss": 0.25}, 100)
    first.scalar("eval/return", 2.5, 200)
    first.close()
    with path.open("a") as file:  # a kill in the middle of a row
        file.write("300,eval/ret")
    second = Logger([CsvSink(path)])
    second.scalar("eval/return", 2.5, 200)  # logged again by the resumed run
    second.scalar("eval/return", 3.5, 300)
    second.scalar("eval/return", 3.5, 300)
    second.close()
    assert _rows(path) == [("step", "tag", "value"), ("100", "eval/return", "1.5"),
                           ("100", "train/loss", "0.25"), ("200", "eval/return", "2.5"),
                           ("300", "eval/return", "3.5")]


def test_a_scalars_file_that_is_not_one_is_named(tmp_path):
    path = tmp_path / "scalars.csv"
    path.write_text("a,b\n1,2\n")
    with pytest.raises(ValueError, match="scalars.csv: not a scalars file"):
        CsvSink(path)


def test_a_reopened_tensorboard_sink_writes_each_tag_and_step_once(tmp_path):
    first = TensorBoardSink(tmp_path)
    first.scalar("eval/return", 1.0, 10)
    first.text("hparams", "{}", 0)
    first.close()
    second = TensorBoardSink(tmp_path)
    second.scalar("eval/return", 1.0, 10)
    second.text("hparams", "{}", 0)
    second.scalar("eval/return", 2.0, 20)
    second.close()
    from tensorboard.backend.event_processing.event_file_loader import EventFileLoader

    written = [(value.tag, event.step) for path in sorted(tmp_path.glob("events.*"))
               for event in EventFileLoader(str(path)).Load() for value in event.summary.value]
    assert sorted(written) == [("eval/return", 10), ("eval/return", 20),
                               ("hparams/text_summary", 0)]
    assert _events_held(tmp_path) == set(written)


def test_a_resumed_run_writes_its_hyperparameters_once(tmp_path):
    for _ in range(2):  # the run, then its resume after a kill before it said "done"
        sink = TensorBoardSink(tmp_path)
        sink.hparams({"seed": 0}, {"eval/return": 1.5})
        sink.close()
    from tensorboard.backend.event_processing.event_file_loader import EventFileLoader

    written = [value.tag for path in sorted(tmp_path.glob("events.*"))
               for event in EventFileLoader(str(path)).Load() for value in event.summary.value]
    assert sorted(written) == ["_hparams_/experiment", "_hparams_/session_end_info",
                               "_hparams_/session_start_info", "hparams/eval/return"]
