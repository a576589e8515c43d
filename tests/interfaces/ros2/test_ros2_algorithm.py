"""``ros2:`` algorithms: a ROS 2 controller node, started by mimics, drives ``mimics run``
and battery runs, each on a DDS domain of its own; all DDS traffic on loopback.

The nodes are the suite's own: the Cyclone DDS controller written from ROS 2's
conventions (``controller.py``, not mimics' code) and the C++ Fast DDS peer built from
ROS 2's message definitions (``fastdds_peer.py``).
"""

from __future__ import annotations

import json
import socket
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from cyclonedds.domain import Domain, DomainParticipant

from mimics.interfaces.ros2.private_domain import (
    PORT_BASE,
    PRIVATE_DOMAINS,
    domain_ports,
    reserve_domain,
)
from mimics.world.errors import MimicsError
from tests.interfaces.ros2.fastdds_peer import PROFILE, build_peer
from tests.interfaces.ros2.loopback import cyclone_config, next_domain
from tests.processes import left_running, marked_environment

REPO = Path(__file__).resolve().parents[3]
CONTROLLER = REPO / "tests" / "interfaces" / "ros2" / "controller.py"
INHERITED = 101  # the ROS_DOMAIN_ID the tests' mimics inherits: never a run's own
ROBOTS = 2


@pytest.fixture
def env() -> Iterator[tuple[dict[str, str], str]]:
    """The environment of mimics and (inherited) its nodes: DDS on loopback only, for
    Cyclone and Fast DDS; ``tests`` importable by the controller; a marker to find
    processes left running."""
    environ, marker = marked_environment()
    environ |= {"CYCLONEDDS_URI": cyclone_config(), "FASTRTPS_DEFAULT_PROFILES_FILE": str(PROFILE),
                "PYTHONPATH": str(REPO), "ROS_DOMAIN_ID": str(INHERITED)}
    for name in ("ROS_DISCOVERY_SERVER", "FASTDDS_ENVIRONMENT_FILE",
                 "FASTDDS_DEFAULT_PROFILES_FILE"):  # what would send Fast DDS elsewhere
        environ.pop(name, None)
    yield environ, marker
    assert left_running(marker) == []  # nodes stopped, or killed with their mimics


def mimics(environ: dict[str, str], *args: str, cwd: Path | None = None
           ) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "mimics", *args], env=environ, cwd=cwd,
                          capture_output=True, text=True, timeout=240, check=False)


def controller(marks: Path) -> str:
    """The controller as a ``ros2:`` algorithm; it creates ``marks/SEED-DOMAIN`` mid-run."""
    return f"ros2:{CONTROLLER} {{robots}} {marks}/{{seed}}-{{domain}}"


def run_alone(environ: dict[str, str], algorithm: str, seed: int, folder: Path) -> dict:
    done = mimics(environ, "run", "line", algorithm, "--robots", str(ROBOTS), "--seed",
                  str(seed), "--time", "60", "--out", str(folder))
    assert done.returncode == 0, done.stdout + done.stderr
    return json.loads((folder / "summary.json").read_text())


def mark_domain(marks: Path, seed: int) -> int:
    """The domain the run of ``seed`` gave its node (from the mark's name)."""
    [mark] = marks.glob(f"{seed}-*")
    return int(mark.name.split("-")[1])


def test_the_controller_node_brings_the_robots_home_twice_with_one_digest(
        env: tuple[dict[str, str], str], tmp_path: Path) -> None:
    environ, _ = env
    digests = []
    for attempt in ("first", "second"):
        marks = tmp_path / f"marks-{attempt}"
        marks.mkdir()
        summary = run_alone(environ, controller(marks), 1, tmp_path / attempt)
        assert (summary["status"], summary["algorithm"], summary["reached_goal"]) == (
            "completed", "ros2-controller", ROBOTS), summary
        digests.append(summary["trajectory_digest"])
        # the node got its run's seed and a private domain, never the inherited one
        domain = mark_domain(marks, 1)
        assert domain in PRIVATE_DOMAINS and domain != INHERITED
    assert digests[0] == digests[1]


def test_the_fastdds_peer_as_a_ros2_algorithm_brings_the_robots_home(
        env: tuple[dict[str, str], str], tmp_path: Path) -> None:
    environ, _ = env
    peer = build_peer()
    summary = run_alone(environ, f"ros2:{peer} --robots {{robots}} --domain {{domain}} "
                        "--timeout 120", 1, tmp_path / "run")
    assert (summary["status"], summary["algorithm"], summary["reached_goal"]) == (
        "completed", "ros2-mimics_ros2_peer", ROBOTS), summary


def test_a_two_worker_battery_runs_each_run_on_its_own_domain(
        env: tuple[dict[str, str], str], tmp_path: Path) -> None:
    environ, _ = env
    marks = tmp_path / "marks"
    marks.mkdir()
    battery = tmp_path / "battery.toml"
    battery.write_text(f'''[battery]
algorithms = ["{controller(marks)}"]
seeds = [0, 1]
time = 60
ros_timeout = 20

[[scenarios]]
name = "line"
robots = {ROBOTS}
''')
    done = mimics(environ, "battery", "run", str(battery), "--out", str(tmp_path / "out"),
                  "--workers", "2")
    assert done.returncode == 0, done.stdout + done.stderr
    folders = sorted((tmp_path / "out" / "runs").iterdir())
    assert len(folders) == 2
    # the same runs alone (two mimics processes at once: each on a domain of its own too)
    alone = [subprocess.Popen([sys.executable, "-m", "mimics", "run", "line",
                               f"ros2:{CONTROLLER} {{robots}}", "--robots", str(ROBOTS),
                               "--seed", str(seed), "--time", "60", "--out",
                               str(tmp_path / f"alone-{seed}")], env=environ,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
             for seed in (0, 1)]
    for process in alone:
        output, _ = process.communicate(timeout=240)
        assert process.returncode == 0, output
    for seed, folder in enumerate(folders):
        summary = json.loads((folder / "summary.json").read_text())
        assert (summary["seed"], summary["status"], summary["reached_goal"]) == (
            seed, "completed", ROBOTS), summary
        # had the runs seen each other's commands, they would differ from the runs alone
        by_itself = json.loads((tmp_path / f"alone-{seed}" / "summary.json").read_text())
        assert summary["trajectory_digest"] == by_itself["trajectory_digest"]
        assert mark_domain(marks, seed) != INHERITED


def test_a_node_that_exits_at_once_is_named_in_one_line(
        env: tuple[dict[str, str], str], tmp_path: Path) -> None:
    environ, _ = env
    (tmp_path / "quitter.py").write_text("import sys\nsys.exit(3)\n")
    done = mimics(environ, "run", "line", "ros2:quitter.py", "--robots", "2", cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr.strip().splitlines() == [
        f"mimics: error: the controller node '{sys.executable} {tmp_path / 'quitter.py'}' "
        "exited with status 3 before it connected"]


def test_a_node_that_never_connects_ends_the_run_at_the_ros_timeout(
        env: tuple[dict[str, str], str], tmp_path: Path) -> None:
    environ, _ = env
    (tmp_path / "silent.py").write_text("import time\ntime.sleep(600)\n")
    done = mimics(environ, "run", "line", "ros2:silent.py", "--robots", "2",
                  "--ros-timeout", "1", cwd=tmp_path)
    assert done.returncode == 2
    assert "no controller node for robot 0 within 1 s (--ros-timeout sets it)" in done.stderr
    # (the env fixture checks that the node was stopped)


@pytest.mark.parametrize(("reference", "expected"), [
    ("ros2:", "expected ros2:PROGRAM [ARGS...]"),
    ("ros2:--names=stage", "expected ros2:PROGRAM [ARGS...]"),
    ("ros2:no_such_node.py {robots}", "no program"),
])
def test_a_bad_ros2_reference_is_refused_with_status_2(
        env: tuple[dict[str, str], str], tmp_path: Path, reference: str, expected: str) -> None:
    environ, _ = env
    done = mimics(environ, "run", "line", reference, cwd=tmp_path)
    assert done.returncode == 2
    assert done.stderr.startswith(f"mimics: error: algorithm '{reference}': ")
    assert expected in done.stderr and "Traceback" not in done.stderr


# -- the private domain ------------------------------------------------------

def test_a_reserved_domain_is_not_given_again_until_released() -> None:
    first, second = next_domain(), next_domain()
    held = reserve_domain([first, second], environ={})
    assert held.domain == first
    other = reserve_domain([first, second], environ={})
    assert other.domain == second
    with pytest.raises(MimicsError, match="no free DDS domain"):
        reserve_domain([first, second], environ={})
    held.release()
    again = reserve_domain([first, second], environ={})
    assert again.domain == first
    for reservation in (other, again):
        reservation.release()


def test_a_domain_a_dds_participant_is_on_is_skipped() -> None:
    used, free = next_domain(), next_domain()
    # Cyclone DDS itself binds the ports of the domain it joins (loopback, index auto)
    domain = Domain(used, cyclone_config())
    participant = DomainParticipant(used)
    try:
        picked = reserve_domain([used, free], environ={})
        assert picked.domain == free
        picked.release()
    finally:
        del participant, domain


def test_a_bound_discovery_port_or_the_inherited_domain_is_skipped() -> None:
    first, second, third = next_domain(), next_domain(), next_domain()
    # participant 0's discovery port (7410 + 250 d): the RTPS port mapping, computed here
    assert domain_ports(first)[2] == PORT_BASE + 250 * first + 10
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as user:
        user.bind(("127.0.0.1", 7410 + 250 * first))
        picked = reserve_domain([first, second, third],
                                environ={"ROS_DOMAIN_ID": str(second)})
    assert picked.domain == third
    picked.release()


def test_processes_in_parallel_never_share_a_domain(tmp_path: Path) -> None:
    """Four processes reserve at once from the same two domains: two get one each and
    hold it, the others are refused (nobody gets a domain already held)."""
    first, second = next_domain(), next_domain()
    script = (f"import sys, time\nfrom mimics.interfaces.ros2.private_domain import "
              f"reserve_domain\ntry:\n    held = reserve_domain([{first}, {second}], {{}})\n"
              "except Exception:\n    print('none', flush=True)\nelse:\n"
              "    print(held.domain, flush=True)\n    sys.stdin.read()\n")
    children = [subprocess.Popen([sys.executable, "-c", script], stdin=subprocess.PIPE,
                                 stdout=subprocess.PIPE, text=True) for _ in range(4)]
    try:
        answers = sorted(child.stdout.readline().strip()  # type: ignore[union-attr]
                         for child in children)
    finally:
        for child in children:
            child.communicate("")
    assert answers == sorted([str(first), str(second), "none", "none"])
