"""The Dask path against a real LocalCluster on loopback: same database, same results."""

from __future__ import annotations

from pathlib import Path

import distributed
import pytest

from mimics.batteries import run_battery, runs_table
from mimics.records.runner import prepare
from mimics.world.errors import MimicsError
from tests.batteries.helpers import fault, write_battery


def test_battery_on_a_local_dask_cluster(tmp_path: Path) -> None:
    path = write_battery(tmp_path / "b.toml", ["go_to_goal", fault("exit_3")], seeds=[1, 2],
                         time=2.0, scenarios=[{"name": "line", "robots": 2}])
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        result = run_battery(path, tmp_path / "b", dask=cluster.scheduler_address,
                             progress=False)
    assert result.counts == {"done": 2, "crashed": 2}
    table = runs_table(tmp_path / "b")
    done = table[table["state"] == "done"]
    for row in done.itertuples():
        expected = prepare("line", "go_to_goal", robots=2, time=2.0, seed=row.seed).run()
        summary = expected.summary()
        assert (row.reached_goal, row.collisions, row.sim_time) == (
            summary["reached_goal"], summary["collisions"], summary["sim_time"])
        assert row.worker.startswith("tcp://127.0.0.1:")
        assert Path(row.folder, "summary.json").exists()
    crashed = table[table["state"] == "crashed"]
    assert set(crashed["error"]) == {"the worker process died during the run (exit code 3)"}


def test_an_unreachable_scheduler_is_one_line_and_nothing_is_written(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from mimics.batteries import dask_backend

    monkeypatch.setattr(dask_backend, "CONNECT_TIMEOUT", 1.0)
    path = write_battery(tmp_path / "b.toml", ["go_to_goal"])
    with pytest.raises(MimicsError, match="cannot reach the scheduler"):
        run_battery(path, tmp_path / "b", dask="tcp://127.0.0.1:9", progress=False)
    assert not (tmp_path / "b").exists()


def test_a_stopping_rule_battery_on_dask_runs_the_seeds_local_workers_run(
        tmp_path: Path) -> None:
    until = {"metric": "path_length", "half_width": 0.05, "min_seeds": 3, "max_seeds": 6}
    path = write_battery(tmp_path / "b.toml", [fault("stand_still"), fault("random_speed")],
                         time=4.0, timeout=30.0, until=until,
                         scenarios=[{"name": "line", "robots": 1, "random_yaw": False}])
    path.write_text(path.read_text().replace("seeds = 1\n", ""))
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster:
        run_battery(path, tmp_path / "dask", dask=cluster.scheduler_address, progress=False)
    run_battery(path, tmp_path / "local", workers=2, progress=False)
    columns = ["algorithm", "seed", "state", "path_length"]
    on_dask, local = (runs_table(tmp_path / name)[columns].sort_values(["algorithm", "seed"])
                      .reset_index(drop=True) for name in ("dask", "local"))
    assert on_dask.equals(local)
    # standing still never varies: no stop on a sample without spread, so max_seeds (unmet)
    assert on_dask.groupby("algorithm")["seed"].max().to_dict() == {"stand_still": 6,
                                                                   "random_speed": 6}
