"""The Python API refuses enormous numbers, wrong types and aliasing folders at its edge:
one ``MimicsError`` naming the argument, before anything runs or is written."""

from __future__ import annotations

from pathlib import Path

import pytest

import mimics
from mimics.world.errors import MimicsError
from mimics.world.limits import MAX_IMAGE_SIDE, MAX_TIME
from tests.fuzzing import BATTERY_TOML, make_run_folder, snapshot

SMALL = {"robots": 2, "time": 0.3}


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_run_folder(tmp_path_factory.mktemp("api") / "run")


@pytest.mark.parametrize(("options", "named"), [
    ({"time": 1e300}, "time"), ({"time": 1e308}, "time"), ({"time": MAX_TIME * 2}, "time"),
    ({"time": True}, "time"), ({"time": "5"}, "time"), ({"time": [1.0]}, "time"),
    ({"wall_limit": 1e300}, "wall_limit"), ({"wall_limit": "x"}, "wall_limit"),
    ({"params": [1]}, "params"), ({"params": "robots=2"}, "params"), ({"params": {1: 2}}, "params"),
    ({"observers": 5}, "observers"), ({"out": 5}, "out"), ({"out": ""}, "out"),
    ({"record_scans": "no"}, "record_scans"), ({"allow_overlap": 1}, "allow_overlap"),
    ({"seed": True}, "seed"), ({"robots": 1e300}, "robots"),
])
def test_simulate_names_the_argument(options: dict, named: str, tmp_path: Path,
                                     monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    with pytest.raises(MimicsError, match=rf"^{named}\b") as error:
        mimics.simulate("line", "go_to_goal", **{**SMALL, **options})
    assert "\n" not in str(error.value)
    assert list(tmp_path.iterdir()) == []  # nothing written


def test_simulate_never_records_over_the_scenario_file_it_reads(run_folder: Path,
                                                                tmp_path: Path) -> None:
    import shutil

    folder = shutil.copytree(run_folder, tmp_path / "run")
    before = snapshot(folder)
    with pytest.raises(MimicsError, match=r"^out .*scenario\.toml, which is the scenario file"):
        mimics.simulate(folder / "scenario.toml", "go_to_goal", time=0.3, out=folder)
    assert snapshot(folder) == before


@pytest.mark.parametrize("value", [5, None, ["run"], b"run"])
def test_load_run_names_a_path_of_the_wrong_type(value: object) -> None:
    with pytest.raises(MimicsError, match=r"^load_run: path: expected a path"):
        mimics.load_run(value)  # type: ignore[arg-type]


def test_save_refuses_its_own_folder_a_folder_inside_it_and_a_foreign_folder(
        run_folder: Path, tmp_path: Path) -> None:
    import shutil

    folder = shutil.copytree(run_folder, tmp_path / "run")
    loaded = mimics.load_run(folder)
    before = snapshot(folder)
    for target, message in ((folder, "the run's own folder"), (folder / "copy", "inside"),
                            (tmp_path, "holds"), (5, "expected a path")):
        with pytest.raises(MimicsError, match=message):
            loaded.save(target)  # type: ignore[arg-type]
        assert snapshot(folder) == before
    mine = tmp_path / "mine"
    mine.mkdir()
    (mine / "notes.md").write_text("my notes")
    memory = mimics.simulate("line", "go_to_goal", **SMALL)
    for view in (loaded, memory):
        with pytest.raises(MimicsError, match=r"mine: not empty, it holds notes\.md"):
            view.save(mine)
    assert [p.name for p in mine.iterdir()] == ["notes.md"]
    assert memory.save(tmp_path / "new") == tmp_path / "new"  # a new folder is fine


def test_show_and_animate_refuse_sizes_no_renderer_can_allocate(run_folder: Path) -> None:
    for options, named in (({"width_px": MAX_IMAGE_SIDE + 1}, "width_px"),
                           ({"width_px": "640"}, "width_px"), ({"fps": 1e300}, "fps"),
                           ({"trail": 1e300}, "trail"), ({"beams_of": -1}, "robot_beams"),
                           ({"autoplay": "yes"}, "autoplay"), ({"speed": "fast"}, "speed"),
                           ({"widht_px": 10}, "widht_px")):
        with pytest.raises(MimicsError, match=named):
            mimics.show("line", "go_to_goal", widget=False, **SMALL, **options)
    loaded = mimics.load_run(run_folder)
    with pytest.raises(MimicsError, match="width_px"):
        loaded.animate(width_px=10**9)
    with pytest.raises(MimicsError, match="height_px"):
        loaded.plot(height_px=1e308)  # type: ignore[arg-type]


@pytest.mark.parametrize(("options", "named"), [
    ({"workers": "2"}, "workers"), ({"workers": True}, "workers"), ({"out": 5}, "out"),
    ({"progress": "x"}, "progress"), ({"dask": 5}, "dask"),
])
def test_run_battery_names_the_argument_before_anything_is_created(
        options: dict, named: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (tmp_path / "b.toml").write_text(BATTERY_TOML)
    with pytest.raises(MimicsError, match=rf"^run_battery: {named}"):
        mimics.run_battery("b.toml", **options)
    assert [p.name for p in tmp_path.iterdir()] == ["b.toml"]


@pytest.mark.parametrize(("key", "value"), [("time", 1e300), ("time", 1e12), ("timeout", 1e308),
                                            ("time", True), ("timeout", "60")])
def test_run_battery_refuses_enormous_or_mistyped_times_in_a_dict(
        key: str, value: object, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    spec = {"battery": {"algorithms": ["go_to_goal"], "seeds": 1, key: value},
            "scenarios": [{"name": "line", "robots": 2}]}
    with pytest.raises(MimicsError, match=rf"\[battery\] {key}: expected a positive number"):
        mimics.run_battery(spec)
    assert list(tmp_path.iterdir()) == []
