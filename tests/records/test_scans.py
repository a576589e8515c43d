"""scans.parquet: the recorded scans are the engine's (within the quantum), compactly stored."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path
from typing import Any

import numpy as np
import pyarrow.parquet as pq
import pytest

import mimics
from mimics.algorithms import go_to_goal
from mimics.batteries.spec import spec_from_dict
from mimics.batteries.tasks import Task, execute
from mimics.engine.simulation import Simulation
from mimics.interfaces.cli import main
from mimics.records.recorder import RunRecorder
from mimics.records.run_folder import load_run
from mimics.records.scans import METADATA_KEY, range_quantum
from mimics.world.errors import MimicsError
from mimics.world.maps import Map
from mimics.world.robot_types import PIONEER_2DX, PIONEER_3AT, RangerSpec
from mimics.world.scenario import Scenario, Settings
from tests.records.helpers import ScanCapture

NOISY_3AT = dataclasses.replace(PIONEER_3AT, name="noisy3AT", ranger=dataclasses.replace(
    PIONEER_3AT.ranger, sigma=0.05))
LONG_RANGE = dataclasses.replace(PIONEER_2DX, name="long", ranger=RangerSpec(
    name="100 m", fov=np.pi, beams=31, range=100.0))
BLIND = dataclasses.replace(PIONEER_2DX, name="blind", ranger=RangerSpec())


def mixed_scenario() -> Scenario:
    """Four robots of three ranger types (270, 31 and 0 beams) in a 12 x 12 m box; robot 0
    drives into robot 1 (so it stops scanning midway)."""
    rows = [[2, 6, 0, 0, 10, 6], [3.2, 6, np.pi, 0, 1, 6], [6, 2, 0.5, 0, 10, 10],
            [6, 10, 0, 0, 2, 10]]
    return Scenario.from_matrix(rows, Map.box(12, 12), [NOISY_3AT, LONG_RANGE, BLIND],
                                settings=Settings(dt=0.1, time_limit=3.0), name="mixed",
                                type_index=[0, 0, 1, 2])


def record_with_capture(folder: Path, every: int = 1, **options: Any) -> ScanCapture:
    capture = ScanCapture()
    recorder = RunRecorder(folder, record_scans=True, every=every, robot_logs="off", **options)
    Simulation(mixed_scenario(), go_to_goal, seed=3, observers=[capture, recorder]).run()
    return capture


def test_recorded_scans_are_the_engine_scans_within_half_a_quantum(tmp_path: Path) -> None:
    capture = record_with_capture(tmp_path / "run")
    scans = load_run(tmp_path / "run").scans
    assert scans.quantum == 0.002  # the 100 m ranger needs 2 mm steps (65535 codes)
    assert len(scans) == len(capture.seen)
    recorded_steps = {}
    for robot in range(3):
        kind = mixed_scenario().robot_type(robot)
        mine = scans.robot(robot)
        assert mine.ranges.shape[1] == kind.ranger.beams
        assert np.array_equal(mine.angles, np.array(kind.ranger.beam_offsets()))
        assert mine.max_range == kind.ranger.range
        assert np.allclose(mine.times, mine.steps * 0.1, atol=1e-9)
        recorded_steps[robot] = mine.steps.tolist()
        for step, ranges, hits in zip(mine.steps, mine.ranges, mine.hits, strict=True):
            engine, owner = capture.seen[(int(step), robot)]
            assert np.max(np.abs(ranges - engine)) <= scans.quantum / 2 + 1e-9
            assert np.array_equal(hits, owner != -2)
    # robot 0 ran into robot 1: both stop scanning at the collision step, robot 2 goes on
    assert recorded_steps[0] == recorded_steps[1] != recorded_steps[2]
    assert recorded_steps[2] == list(range(len(recorded_steps[2])))
    assert scans.robot(3).ranges.shape == (0, 0)  # a robot without a ranger has no rows
    assert len(scans.robot(0).steps) < 25  # it did stop early (the run has 30 steps)


def test_every_records_the_scans_of_the_full_steps_and_the_last(tmp_path: Path) -> None:
    record_with_capture(tmp_path / "run", every=4)
    run = load_run(tmp_path / "run")
    steps = run.scans.robot(2).steps.tolist()
    last = run.summary["steps"]
    assert steps == sorted({*range(0, last + 1, 4), last})
    assert run.summary["records"]["scan_rows"] == len(run.scans)


def test_layout_is_stored_once_per_type_in_the_file_metadata(tmp_path: Path) -> None:
    record_with_capture(tmp_path / "run")
    metadata = json.loads(pq.read_schema(tmp_path / "run" / "scans.parquet").metadata[
        METADATA_KEY])
    assert [t["name"] for t in metadata["types"]] == ["noisy3AT", "long", "blind"]
    assert len(metadata["types"][0]["angles"]) == 270 and metadata["types"][2]["angles"] == []
    assert metadata["robot_type"] == [0, 0, 1, 2] and metadata["quantum"] == 0.002
    table = pq.read_table(tmp_path / "run" / "scans.parquet")
    assert str(table.schema.field("ranges").type) == "list<element: uint16>"


def test_a_killed_run_keeps_its_scans_in_parts(tmp_path: Path) -> None:
    capture = ScanCapture()
    recorder = RunRecorder(tmp_path / "run", record_scans=True, robot_logs="off", flush_rows=8)
    sim = Simulation(mixed_scenario(), go_to_goal, seed=3, observers=[capture, recorder])
    sim.start()
    for _ in range(6):
        sim.step()
    recorder.flush()  # then the process dies: no merge, no summary.json
    run = load_run(tmp_path / "run")
    assert not run.complete and run.has_scans
    assert len(run.scans) == len(capture.seen) and len(run.scans.robot(2).steps) == 7


@pytest.mark.parametrize(("longest", "quantum"), [(2.0, 0.001), (65.535, 0.001),
                                                  (65.536, 0.002), (131.07, 0.002),
                                                  (131.071, 0.003)])
def test_quantum_is_the_smallest_whole_millimetre_count_that_fits_16_bits(
        longest: float, quantum: float) -> None:
    assert range_quantum(longest) == pytest.approx(quantum)
    assert round(longest / range_quantum(longest)) <= 65535


def test_runs_without_the_option_have_no_scans(tmp_path: Path) -> None:
    mimics.simulate("line", "go_to_goal", robots=2, time=0.5, seed=1, out=tmp_path / "run",
                    record_scans=True)
    assert load_run(tmp_path / "run").has_scans
    # a new run in the same folder, without scans, removes the old ones
    mimics.simulate("line", "go_to_goal", robots=2, time=0.5, seed=1, out=tmp_path / "run")
    run = load_run(tmp_path / "run")
    assert not run.has_scans and not (tmp_path / "run" / "scans.parquet").exists()
    with pytest.raises(MimicsError, match=r"no laser scans recorded.*--record-scans"):
        _ = run.scans
    with pytest.raises(MimicsError, match="give out=FOLDER"):
        mimics.simulate("line", "go_to_goal", robots=2, time=0.5, record_scans=True)


def test_cli_run_records_scans(tmp_path: Path) -> None:
    code = main(["run", "line", "go_to_goal", "--robots", "2", "--time", "0.5",
                 "--out", str(tmp_path / "run"), "--record-scans", "--robot-logs", "off"])
    assert code == 0
    scans = load_run(tmp_path / "run").scans
    assert len(scans) == 2 * 6 and scans.robot(0).ranges.shape == (6, 270)


def test_battery_files_take_record_scans(tmp_path: Path) -> None:
    base = {"algorithms": ["go_to_goal"], "seeds": 1, "time": 0.3}
    spec = spec_from_dict({"battery": {**base, "record_scans": True},
                           "scenarios": [{"name": "line", "robots": 2}]})
    assert spec.record_scans
    with pytest.raises(MimicsError, match=r"record_scans: expected true or false, got 'yes'"):
        spec_from_dict({"battery": {**base, "record_scans": "yes"},
                        "scenarios": [{"name": "line", "robots": 2}]})
    task = Task(run_id=1, attempt=1, algorithm="go_to_goal", scenario="line",
                params={"robots": 2}, seed=1, time=0.3, timeout=60.0, policy="abort",
                robot_logs="off", record_every=1, folder=str(tmp_path / "run"),
                record_scans=spec.record_scans)
    outcome = execute(task, "test")
    assert outcome.error in (None, ""), outcome.error
    assert len(load_run(tmp_path / "run").scans) == 2 * 4
