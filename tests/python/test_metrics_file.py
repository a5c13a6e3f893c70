"""hunav.Simulation(metrics=FILE, format=...): hunav_run's --metrics and --format, on HuNavSim's own
metrics.yaml (tests/data/hunav_files/): its selection picks the metrics, its frequency sets the
sample rate and its experiment_tag the tag, unless sample_rate / experiment_tag are given."""
import csv
import subprocess

import pytest

import hunav
from conftest import REPO

HUNAV_METRICS = REPO / "tests" / "data" / "hunav_files" / "metrics.yaml"


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


@pytest.fixture
def metrics_file(tmp_path):
    """HuNavSim's metrics.yaml with social_work off and a 2 Hz frequency (its tag stays '1')."""
    text = HUNAV_METRICS.read_text()
    assert "social_work: true" in text and "frequency: 1.0" in text
    path = tmp_path / "metrics.yaml"
    path.write_text(text.replace("social_work: true", "social_work: false").replace("frequency: 1.0", "frequency: 2.0"))
    return path


def test_metrics_file_as_hunav_run(passing, hunav_run, metrics_file, tmp_path):
    sim = hunav.Simulation(passing, seed=1, planner="dwb", metrics=str(metrics_file), format="hunav_txt")
    assert sim.sample_rate == 2.0 and sim.experiment_tag == "1"
    info = sim.run()
    metrics = sim.metrics()
    assert "social_work" not in metrics and "path_length" in metrics and "social_force_on_robot" in metrics
    sim.save(str(tmp_path / "py"))
    subprocess.run([hunav_run, "--scenario", passing, "--planner", "dwb", "--seed", "1", "--metrics",
                    str(metrics_file), "--format", "hunav_txt", "--out", str(tmp_path / "cli"), "--quiet"],
                   check=True, capture_output=True)
    py_rows, cli_rows = rows(tmp_path / "py" / "metrics.csv"), rows(tmp_path / "cli" / "metrics.csv")
    assert py_rows == cli_rows and py_rows[0]["experiment_tag"] == "1"
    assert "social_work" not in py_rows[0]
    # 2 Hz over 25.87 s: samples at 0, 0.5, ..., 25.5, 52 in all (at 1 Hz, the file's own rate: 26;
    # every tick: 2588), each a row for the robot and the 2 people: 156 rows and the header.
    states = (tmp_path / "py" / "states.csv").read_text()
    assert info["time"] == pytest.approx(25.87)
    assert states == (tmp_path / "cli" / "states.csv").read_text()
    assert len(states.splitlines()) == 1 + 3 * 52
    txt = sorted(p.name for p in (tmp_path / "py").glob("*.txt"))
    assert txt and txt == sorted(p.name for p in (tmp_path / "cli").glob("*.txt"))


def test_given_rate_and_tag_win_over_the_file(passing, metrics_file):
    sim = hunav.Simulation(passing, metrics=str(metrics_file), sample_rate=0.0, experiment_tag="mine")
    assert sim.sample_rate == 0.0 and sim.experiment_tag == "mine"
    default = hunav.Simulation(passing)
    assert default.sample_rate == 0.0 and default.experiment_tag == "exp" and default.metrics_file == ""


def test_our_selection_file(passing, tmp_path):
    path = tmp_path / "selection.yaml"
    path.write_text("metrics: {social_work: false, path_length: false}\n")
    runs = []
    for selection in (str(path), ""):
        sim = hunav.Simulation(passing, seed=1, duration=2.0, metrics=selection)
        sim.reset()
        while not sim.done:
            sim.step(0.5, 0.0)
        runs.append(sim.metrics())
    selected, every = runs
    assert set(selected) == set(every) - {"social_work", "path_length"}
    assert all(selected[k] == every[k] for k in selected)  # the same values for the rest


def test_bad_metrics_file_and_format(passing, metrics_file, tmp_path):
    bad = tmp_path / "bad_metrics.yaml"
    bad.write_text(metrics_file.read_text().replace("frequency: 2.0", "frequency: fast"))
    with pytest.raises(hunav.ConfigError, match=r"bad_metrics\.yaml:\d+.*frequency"):
        hunav.Simulation(passing, metrics=str(bad))
    with pytest.raises(hunav.ConfigError, match="nowhere.yaml"):
        hunav.Simulation(passing, metrics=str(tmp_path / "nowhere.yaml"))
    with pytest.raises(ValueError, match="format must be"):
        hunav.Simulation(passing, format="xml")
