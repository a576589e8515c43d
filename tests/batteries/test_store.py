"""The battery database, run outcomes and the report, without worker processes."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from mimics.batteries.driver import battery_lock, finish, lock_holder
from mimics.batteries.report import aggregate, export_table, mean_ci95, runs_table
from mimics.batteries.spec import spec_from_dict
from mimics.batteries.store import BatteryStore
from mimics.batteries.tasks import OUTCOME_FILE, Outcome, execute
from mimics.world.errors import MimicsError
from tests.batteries.helpers import fault


def make_store(folder: Path, seeds: int = 3, **battery: object) -> BatteryStore:
    spec = spec_from_dict({"battery": {"algorithms": ["go_to_goal"], "seeds": seeds,
                                       "time": 1.0, **battery},
                           "scenarios": [{"name": "line", "robots": [1, 2]}]})
    return BatteryStore.create(folder, spec)


def outcome(run_id: int, attempt: int, state: str = "done", **counts: int) -> Outcome:
    base = {"robots": 2, "reached_goal": 2, "collisions": 0, "escaped": 0, "deadlocks": 0,
            "livelocks": 0, "exceptions": 0}
    return Outcome(run_id, attempt, state, status="completed", started=1.0, ended=2.0,
                   wall_time=1.0, sim_time=1.0, counts={**base, **counts})


def test_every_run_is_listed_pending_before_any_starts(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b")
    assert store.counts() == {"pending": 6}
    db = sqlite3.connect(tmp_path / "b" / "battery.db")
    assert db.execute("PRAGMA journal_mode").fetchone()[0] == "wal"
    rows = store.rows()
    assert [r["seed"] for r in rows] == [1, 2, 3, 1, 2, 3]
    assert json.loads(rows[3]["params"]) == {"robots": 2}
    assert rows[0]["folder"] == "00001-go_to_goal-line-robots=1-s1"
    with pytest.raises(MimicsError, match="already holds a battery"):
        make_store(tmp_path / "b")


def test_start_record_and_stale_attempts(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b")
    assert store.start(1) == 1
    assert store.counts() == {"pending": 5, "running": 1}
    assert not store.record(outcome(1, attempt=2))  # not the running attempt
    assert store.record(outcome(1, attempt=1, collisions=1))
    row = store.rows()[0]
    assert (row["state"], row["attempts"], row["collisions"]) == ("done", 1, 1)
    assert not store.record(outcome(1, attempt=1))  # no longer running


def test_requeue_adopts_finished_folders_and_requeues_the_rest(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b")
    for run_id in (1, 2, 3):
        store.start(run_id)
    # run 1 was renamed into place but the battery died before the commit
    folder = store.run_folder(1)
    folder.mkdir(parents=True)
    (folder / OUTCOME_FILE).write_text(outcome(1, 1, collisions=2).to_json())
    # run 2's folder belongs to an older attempt
    store.run_folder(2).mkdir(parents=True)
    (store.run_folder(2) / OUTCOME_FILE).write_text(outcome(2, 0).to_json())
    adopted, requeued = store.requeue_running()
    assert (adopted, requeued) == (1, 2)
    states = {r["id"]: (r["state"], r["collisions"]) for r in store.rows()}
    assert states[1] == ("done", 2)
    assert states[2][0] == states[3][0] == "pending"


def test_reset_failed_only_touches_failed_states(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b")
    for run_id, state in ((1, "error"), (2, "timeout"), (3, "crashed"), (4, "done")):
        store.start(run_id)
        store.record(outcome(run_id, 1, state))
    assert store.reset_failed(("timeout",)) == 1
    assert store.reset_failed() == 2
    assert store.counts() == {"pending": 5, "done": 1}
    with pytest.raises(MimicsError, match="--state"):
        store.reset_failed(("done",))


def test_finish_renames_the_folder_then_commits(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b")
    spec = store.spec()
    attempt = store.start(4)
    task = store.task(4, attempt, spec, tmp_path / "b" / "tmp" / "x")
    assert (task.algorithm, task.params, task.seed, task.time) == ("go_to_goal",
                                                                   {"robots": 2}, 1, 1.0)
    result = execute(task, "here")
    assert (result.state, result.status, result.counts["robots"]) == ("done", "time_limit", 2)
    finish(store, task, result)
    final = store.run_folder(4)
    assert not Path(task.folder).exists()
    assert json.loads((final / "summary.json").read_text())["battery_attempt"] == 1
    assert Outcome.from_json((final / OUTCOME_FILE).read_text()) == result
    assert store.rows()[3]["state"] == "done"


def test_execute_maps_engine_statuses_to_states(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b", policy="deactivate")

    def run(algorithm: str, policy: str = "abort", **params: object) -> Outcome:
        task = store.task(1, 1, store.spec(), tmp_path / algorithm.replace("/", "_"))
        fields = {**task.__dict__, "algorithm": algorithm, "policy": policy,
                  "params": {"robots": 2, **params}}
        return execute(type(task)(**fields), "here")

    raised = run(fault("raise_at_7"))
    assert raised.state == "error"
    assert raised.error.startswith("ValueError in robot 0 at t=0.6 s, ")
    assert raised.error.endswith('raise_at_7.py:7: boom at step 7\n'
                                 '    raise ValueError("boom at step 7")')
    assert 'raise ValueError("boom at step 7")' in raised.traceback
    deactivated = run(fault("raise_at_7"), policy="deactivate")
    assert (deactivated.state, deactivated.counts["exceptions"]) == ("done", 2)
    nan = run(fault("nan"))
    assert nan.state == "error" and "non-finite reference" in nan.error
    unknown = run("go_to_goal", robots=0)
    assert unknown.state == "error" and "could not start" in unknown.error


def test_the_lock_is_exclusive(tmp_path: Path) -> None:
    folder = tmp_path
    assert lock_holder(folder) is None
    with battery_lock(folder):
        assert lock_holder(folder) is not None
        with pytest.raises(MimicsError, match="already running"), battery_lock(folder):
            pass
    assert lock_holder(folder) is None


def test_report_table_aggregates_and_exports(tmp_path: Path) -> None:
    store = make_store(tmp_path / "b", seeds=3)
    for run_id, collisions in ((1, 0), (2, 1), (3, 2)):
        store.start(run_id)
        store.record(outcome(run_id, 1, collisions=collisions))
    store.start(4)
    store.record(Outcome(4, 1, "crashed", error="the worker process died (exit code 3)"))
    store.close()
    table = runs_table(tmp_path / "b")
    assert list(table["misbehaving"]) == [False, True, True, True, False, False]
    assert table["param_robots"].tolist() == [1, 1, 1, 2, 2, 2]
    assert pd.isna(table.loc[3, "collisions"])
    agg = aggregate(table).set_index("parameters")
    one = agg.loc["robots=1"]
    assert (one["runs"], one["done"], one["failed"]) == (3, 3, 0)
    assert one["collisions"] == pytest.approx(1.0)
    assert one["collisions_ci95"] == pytest.approx(4.302653 * 1.0 / np.sqrt(3), rel=1e-5)
    assert (agg.loc["robots=2", "failed"], agg.loc["robots=2", "unfinished"]) == (1, 2)
    csv = pd.read_csv(export_table(table, tmp_path / "t.csv"))
    for column in ("algorithm", "scenario", "seed", "state", "reached_goal", "collisions",
                   "deadlocks", "livelocks", "exceptions", "error"):
        assert column in csv.columns
    assert "traceback" not in csv.columns
    parquet = pd.read_parquet(export_table(table, tmp_path / "t.parquet"))
    assert len(parquet) == 6 and "traceback" in parquet.columns
    assert str(parquet["collisions"].dtype) == "Int64"


def test_mean_ci95_edge_cases() -> None:
    assert np.isnan(mean_ci95(np.array([]))[0])
    assert mean_ci95(np.array([2.0]))[0] == 2.0 and np.isnan(mean_ci95(np.array([2.0]))[1])
    assert mean_ci95(np.array([1.0, 1.0]))[1] == 0.0


def test_progress_is_quiet_off_a_terminal_and_counts_failures() -> None:
    import io

    from rich.console import Console

    from mimics.batteries.progress import BatteryProgress

    quiet = io.StringIO()
    with BatteryProgress(3, console=Console(file=quiet)) as bar:
        bar.advance("done")
        bar.advance("crashed")
    assert quiet.getvalue() == "" and bar.failed == 1
    shown = io.StringIO()
    with BatteryProgress(3, 1, 1, console=Console(file=shown, force_terminal=True,
                                                  width=120)) as bar:
        bar.advance("timeout")
    assert "2/3" in shown.getvalue() and "2 failed" in shown.getvalue()


def test_a_battery_made_before_metrics_and_digests_gains_their_columns(tmp_path: Path) -> None:
    make_store(tmp_path / "b").close()
    with sqlite3.connect(tmp_path / "b" / "battery.db") as db:  # the first schema's table
        db.execute("ALTER TABLE runs DROP COLUMN metrics")
        db.execute("ALTER TABLE runs DROP COLUMN digest")
    store = BatteryStore.open(tmp_path / "b")
    store.start(1)
    done = outcome(1, 1)
    done.metrics, done.digest = {"time_to_goal": 2.5, "path_length": None}, "o:abc"
    assert store.record(done)
    store.close()
    table = runs_table(tmp_path / "b")
    # its time_to_goal was the mean over arrivals: read as such; the restricted mean unknown
    assert table.loc[0, "time_to_goal_arrived"] == 2.5 and table.loc[0, "digest"] == "o:abc"
    assert table["time_to_goal"].isna().all()
    assert np.isnan(table.loc[0, "path_length"]) and table["time_to_goal_arrived"].isna().sum() == 5


def test_add_runs_lists_only_new_runs_with_the_cells_label(tmp_path: Path) -> None:
    from mimics.batteries.spec import RunSpec

    store = make_store(tmp_path / "b", seeds=2)
    first = store.rows()[0]
    runs = [RunSpec(first["algorithm_ref"], "go_to_goal", "line", "line", {"robots": 1}, seed)
            for seed in (2, 3, 4)]
    assert store.add_runs(runs) == [5, 6]  # seed 2 is listed already
    assert store.add_runs(runs) == []
    rows = store.rows()
    assert [(r["seed"], r["state"], r["label"]) for r in rows[4:]] == [
        (3, "pending", "robots=1"), (4, "pending", "robots=1")]
    assert rows[5]["folder"] == "00006-go_to_goal-line-robots=1-s4"


def test_execute_reads_the_trajectory_digest_of_summary_json(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import mimics.records.runner as runner

    original = runner.run_to_folder
    poses = {"value": "aa11"}

    def with_digest(sim: object, folder: object, **options: object) -> object:
        # the recorder of the seed work writes `trajectory_digest` into summary.json
        extra = {**options.pop("extra", {}), "trajectory_digest": poses["value"]}
        return original(sim, folder, extra=extra, **options)

    monkeypatch.setattr(runner, "run_to_folder", with_digest)
    store = make_store(tmp_path / "b")

    def digest(seed: int, name: str) -> str:
        task = store.task(1, 1, store.spec(), tmp_path / name)
        return execute(type(task)(**{**task.__dict__, "seed": seed}), "here").digest

    first, again = digest(1, "one"), digest(1, "again")
    assert first.startswith("t:") and first == again  # same poses, same outcome
    poses["value"] = "bb22"
    assert digest(1, "three") != first  # other poses (same outcome): another run

    def without_digest(sim: object, folder: Path, **options: object) -> object:
        # a summary.json of a run recorded before runs had digests
        result = original(sim, folder, **options)
        path = Path(folder) / "summary.json"
        summary = json.loads(path.read_text())
        del summary["trajectory_digest"]
        path.write_text(json.dumps(summary))
        return result

    monkeypatch.setattr(runner, "run_to_folder", without_digest)
    assert digest(4, "four").startswith("o:")  # no trajectory digest: the outcome alone
    monkeypatch.setattr(runner, "run_to_folder", original)
    # the engine's own digest: the same seed gives the same run, another seed another
    assert digest(5, "five") == digest(5, "five-again") != digest(6, "six")
    summary = json.loads((tmp_path / "one" / "summary.json").read_text())
    assert summary["trajectory_digest"] == "aa11"
