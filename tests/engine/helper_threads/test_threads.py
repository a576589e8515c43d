"""Whole runs are bit-identical whatever the number of Numba threads."""

import hashlib
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from mimics.algorithms import deployment_team, wall_aware
from mimics.catalog import load_scenario
from mimics.engine.simulation import Simulation
from tests.threads import thread_count


def run_digest(scenario, algorithm, threads: int) -> str:
    with thread_count(threads):
        sim = Simulation(scenario, algorithm, seed=3, time_limit=6.0)
        sim.run()
    digest = hashlib.sha256()
    for array in (sim.state.pose, sim.state.scan, sim.state.scan_hit, sim.state.status,
                  sim.state.odometry):
        digest.update(np.ascontiguousarray(array).tobytes())
    digest.update(repr([(e.time, e.robot, e.kind) for e in sim.events]).encode())
    return digest.hexdigest()


@pytest.mark.parametrize("name, algorithm", [("obstacle_room", deployment_team),
                                             ("circle_swap", wall_aware)])
def test_one_thread_and_all_threads_give_the_same_run(name, algorithm):
    scenario = load_scenario(name, robots=24)
    one = run_digest(scenario, algorithm, 1)
    many = run_digest(scenario, algorithm, 2)
    assert one == many


def _digest_in_child(queue, scenario, threads):
    queue.put(run_digest(scenario, deployment_team, threads))


def test_a_forked_process_runs_on_threads_of_its_own():
    """A fork copies the ray kernel's thread pool but none of its threads: the child
    must start its own (a stale pool would wait for ever)."""
    import multiprocessing

    scenario = load_scenario("obstacle_room", robots=24)
    here = run_digest(scenario, deployment_team, 2)  # the parent's pool exists now
    context = multiprocessing.get_context("fork")
    queue = context.Queue()
    child = context.Process(target=_digest_in_child, args=(queue, scenario, 2))
    child.start()
    try:
        assert queue.get(timeout=120) == here
    finally:
        child.join(10)
        if child.is_alive():
            child.kill()


NUMBA_POOL = """
import json, numba
from numba.np.ufunc import parallel
from mimics.algorithms import deployment_team
from mimics.catalog import load_scenario
from mimics.engine.helper_threads.threads import helpers_worth
from mimics.engine.simulation import Simulation

Simulation(load_scenario("obstacle_room", robots=6), deployment_team, seed=1, time_limit=0.5).run()
started = parallel._is_initialized  # Numba's own pool, which mimics never uses
worth = helpers_worth(8)
numba.set_num_threads(1)  # the user's knob still counts
print(json.dumps({"started": started, "worth": worth, "after": helpers_worth(8)}))
"""


def test_helpers_follow_numbas_thread_count_without_starting_its_pool():
    env = {**os.environ, "NUMBA_NUM_THREADS": "2"}
    done = subprocess.run([sys.executable, "-c", NUMBA_POOL], capture_output=True, text=True,
                          check=True, env=env)
    seen = json.loads(done.stdout.strip().splitlines()[-1])
    assert seen == {"started": False, "worth": 1, "after": 0}
