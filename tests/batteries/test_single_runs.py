"""A battery's runs equal the same runs made one by one (workers reuse nothing that shows)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pyarrow.parquet as pq

from mimics.batteries import run_battery, spec_from_dict
from mimics.batteries.store import BatteryStore
from mimics.records.runner import prepare, run_to_folder

#: summary.json keys that are times, identifiers or per-run bookkeeping
VARYING = ("wall_time", "user_code", "created", "uuid", "step_time", "write_time", "sim_speed",
           "battery_")


def stable(summary: dict[str, Any]) -> dict[str, Any]:
    return {key: stable(value) if isinstance(value, dict) else value
            for key, value in summary.items() if not any(v in key for v in VARYING)}


def test_battery_runs_equal_single_runs(tmp_path: Path) -> None:
    spec = spec_from_dict({
        "battery": {"algorithms": ["go_to_goal", "wall_aware"], "seeds": 2, "time": 4.0,
                    "timeout": 60, "robot_logs": "off"},
        "scenarios": [{"name": "line", "robots": [1, 3, 7]},
                      {"name": "circle_swap", "robots": 6}]})
    result = run_battery(spec, tmp_path / "b", workers=2, progress=False)
    assert result.counts == {"done": 16}
    store = BatteryStore.open(tmp_path / "b")
    try:
        rows = store.rows()
    finally:
        store.close()
    for row in rows:  # each worker ran several of them, one after another
        folder = tmp_path / "b" / "runs" / row["folder"]
        params = json.loads(row["params"])
        alone = tmp_path / "alone" / row["folder"]
        run_to_folder(prepare(row["scenario_ref"], row["algorithm_ref"], time=4.0,
                              seed=row["seed"], wall_limit=60, params=params),
                      alone, robot_logs="off")
        ran = json.loads((folder / "summary.json").read_text())
        single = json.loads((alone / "summary.json").read_text())
        assert stable(ran) == stable(single), row["folder"]
        for table in ("trajectory.parquet", "events.parquet"):
            a = pq.read_table(folder / table)
            b = pq.read_table(alone / table)
            if "user_time" in a.column_names:
                a, b = a.drop(["user_time"]), b.drop(["user_time"])
            assert a.schema == b.schema, (row["folder"], table)
            assert a.to_pandas().equals(b.to_pandas()), (row["folder"], table)  # NaN == NaN
        assert (sorted(p.name for p in folder.iterdir())
                == sorted([*(p.name for p in alone.iterdir()), "battery.json"]))
