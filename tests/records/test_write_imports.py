"""Recording a run imports only what writing it needs: not ``pyarrow.compute``, whose
import (25 to 60 ms) would be a tenth of a short run's whole process."""

import json
import subprocess
import sys
import textwrap

SCRIPT = textwrap.dedent("""
    import json, sys
    from mimics.records.runner import prepare, run_to_folder

    sim = prepare("line", "go_to_goal", robots=3, seed=2, time=0.5)
    run_to_folder(sim, sys.argv[1], robot_logs="on")
    print(json.dumps({name: name in sys.modules for name in ("pyarrow.compute", "pandas")}))
""")


def test_a_recorded_run_with_logs_does_not_import_pyarrow_compute(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-c", SCRIPT, str(out)], capture_output=True,
                          text=True, check=True)
    assert json.loads(done.stdout.strip().splitlines()[-1]) == {"pyarrow.compute": False,
                                                                "pandas": False}
    logs = sorted((out / "robots").glob("*.log"))
    assert len(logs) == 3
    # each log's first row: the start (time 0), its numbers in Arrow's shortest form
    first_row = logs[0].read_text().splitlines()[12]
    assert first_row.startswith("0;") and first_row.endswith(";;")
