"""The inspector's API: a robot's velocities and references per frame (against
trajectory.parquet read directly), its log up to a time (against the CSV parsed by the csv
module), every robot's beams at once (against each robot's own), robot types; and a built-in
scenario opened as the start of a new file (against the catalog's scenario)."""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from fastapi.testclient import TestClient

from mimics.catalog import list_scenarios, load_scenario
from mimics.interfaces.web.runs import LOG_LINES, log_until
from mimics.records.run_folder import load_run
from mimics.world.scenario_files import load_scenario_toml

RUN = "runs/line-go_to_goal-s1"


def test_a_robots_velocities_and_references_at_every_frame(client: TestClient,
                                                            workspace: Path) -> None:
    meta = client.get("/api/runs/meta", params={"path": RUN}).json()
    assert meta["types"] == ["Pioneer3AT"] * 3
    table = pq.read_table(workspace / RUN / "trajectory.parquet").to_pandas()
    for robot in range(3):
        got = client.get("/api/runs/robot", params={"path": RUN, "robot": robot}).json()
        assert got["type"] == "Pioneer3AT"
        mine = table[table["robot"] == robot].sort_values("step")
        assert len(got["v"]) == meta["frames"] == 31
        for frame in (0, 1, 12, 30):  # frame k is step k here (no thinning)
            rows = mine[mine["step"] <= frame]
            row = rows.iloc[-1]  # the robot's last row at or before the frame
            assert [got[c][frame] for c in ("v", "w", "v_ref", "heading_ref")] == [
                row["v"], row["w"], row["v_ref"], row["heading_ref"]]
    moving = client.get("/api/runs/robot", params={"path": RUN, "robot": 0}).json()
    assert max(moving["v"]) > 0.1  # the robots drive towards their goals
    assert client.get("/api/runs/robot", params={"path": RUN, "robot": 3}).status_code == 400


def table_rows(lines: list[str]) -> list[list[str]]:
    """The table rows of a robot log's lines (after its units row), parsed by the csv module
    (this run's messages hold no line break)."""
    units = next(k for k, line in enumerate(lines) if line.startswith("[s];"))
    body = [line for line in lines[units + 1:] if line and not line.startswith("Deactivation")]
    return list(csv.reader(io.StringIO("\n".join(body)), delimiter=";"))


@pytest.mark.parametrize("until", [0.0, 0.7, 1.55, 2.9])
def test_the_log_up_to_a_time_holds_the_csv_rows_up_to_it(client: TestClient,
                                                          workspace: Path,
                                                          until: float) -> None:
    text = load_run(workspace / RUN).log_path(1).read_text(encoding="utf-8")
    log = client.get("/api/runs/log", params={"path": RUN, "robot": 1, "until": until}).json()
    expected = [row for row in table_rows(text.splitlines()) if float(row[0]) <= until]
    assert len(expected) == math.floor(until / 0.1 + 1e-9) + 1  # dt = 0.1 s, from t = 0
    assert table_rows(log["lines"]) == expected
    assert log["lines"][:12] == text.splitlines()[:12]  # the header comes too
    assert not any(line.startswith("Deactivation") for line in log["lines"])
    assert log["skipped"] == 0


def test_the_whole_log_ends_with_the_deactivation(client: TestClient, workspace: Path) -> None:
    text = load_run(workspace / RUN).log_path(2).read_text(encoding="utf-8")
    whole = client.get("/api/runs/log", params={"path": RUN, "robot": 2}).json()
    assert whole["lines"] == text.splitlines()
    late = client.get("/api/runs/log", params={"path": RUN, "robot": 2, "until": 99}).json()
    assert late["lines"] == text.splitlines()


def test_log_until_keeps_quoted_line_breaks_with_their_row_and_the_last_rows() -> None:
    header = ["robot id = 0", "", "time;x;user_msg", "[s];[m];[]"]
    rows = [f"{k / 10:g};{k};" for k in range(LOG_LINES + 10)]
    rows[3] = '0.3;3;"two\nlines"'
    lines = header + "\n".join(rows).split("\n") + ["", "Deactivation: Reached goal"]
    shown, skipped = log_until(lines, 0.35)
    assert shown == [*header, "0;0;", "0.1;1;", "0.2;2;", '0.3;3;"two', 'lines"']
    assert skipped == 0
    shown, skipped = log_until(lines, 1e9)
    assert skipped == 10 and len(shown) == len(header) + LOG_LINES + 2
    assert shown[-1] == "Deactivation: Reached goal"


def test_every_robots_beams_are_each_robots_beams(client: TestClient) -> None:
    for frame in (0, 20):
        every = client.get("/api/runs/all_beams", params={"path": RUN, "frame": frame}).json()
        assert every["every"] == 1
        singles = [client.get("/api/runs/beams", params={"path": RUN, "robot": r,
                                                         "frame": frame}).json()["segments"]
                   for r in range(3)]
        expected = np.array([s for one in singles for s in one])
        assert len(every["segments"]) == len(expected) == 3 * 270
        np.testing.assert_allclose(every["segments"], expected, atol=1e-4)
    assert client.get("/api/runs/all_beams", params={"path": RUN, "frame": 31}).status_code \
        == 400


@pytest.mark.parametrize("name", ["line", "corridor", "circle_swap"])
def test_a_builtin_scenario_opens_and_saves_as_the_same_scenario(client: TestClient,
                                                                 workspace: Path,
                                                                 name: str) -> None:
    assert name in dict(list_scenarios())
    data = client.get("/api/scenarios/builtin", params={"name": name}).json()
    truth = load_scenario(name)
    assert data["name"] == truth.name and len(data["robots"]) == truth.robot_count
    body = {"path": f"scenarios/{name}.toml", "name": data["name"],
            "map": data["map"] or data["map_inline"], "robots": data["robots"],
            "types": data["custom_types"], "settings": {
                k: data["settings"][k] for k in ("time_limit", "goal_tolerance",
                                                 "deadlock_window")},
            "overwrite": False}
    saved = client.put("/api/scenarios/file", json=body)
    assert saved.status_code == 200, saved.text
    back = load_scenario_toml(workspace / "scenarios" / f"{name}.toml")
    np.testing.assert_array_equal(back.stages[:, :3], truth.stages[:, :3])
    np.testing.assert_array_equal(back.goals, truth.goals)
    np.testing.assert_array_equal(back.map.segments, truth.map.segments)
    assert back.map.bounds == truth.map.bounds
    assert [back.robot_type(i) for i in range(back.robot_count)] == [
        truth.robot_type(i) for i in range(truth.robot_count)]
    reopened = client.get("/api/scenarios/file", params={"path": f"scenarios/{name}.toml"})
    assert reopened.json()["map_inline"] == data["map_inline"]


def test_an_unknown_builtin_scenario_is_refused_naming_the_known_ones(client: TestClient
                                                                      ) -> None:
    answer = client.get("/api/scenarios/builtin", params={"name": "nope"})
    assert answer.status_code == 400
    assert "line" in answer.json()["detail"] and "'nope'" in answer.json()["detail"]


def test_every_kth_beam_of_each_robot_when_thinned(workspace: Path) -> None:
    from mimics.interfaces.replay import BeamCaster, replay_data

    data = replay_data(load_run(workspace / RUN))
    caster = BeamCaster(data.scenario)
    pose, status = data.pose[10], data.status[10].copy()
    status[1] = 2  # robot 1 collided: no beams of its own (it is still an obstacle)
    thinned = caster.all_beams(pose, status, every=4)
    singles = [caster.beams(r, pose, status) for r in range(3)]
    assert singles[1] is None
    expected = np.concatenate([singles[0][::4], singles[2][::4]])
    assert thinned.shape == expected.shape == (2 * 68, 2, 2)  # 270 beams: 0, 4, ..., 268
    np.testing.assert_allclose(thinned, expected, atol=1e-9)
