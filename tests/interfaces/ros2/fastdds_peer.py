"""The Fast DDS peer of the ROS 2 tests: built from ``peer/`` once, run on loopback only.

``peer/`` holds ROS 2 Humble's message definitions as IDL (``peer/idl``, one flat folder:
fastddsgen writes its output flat and names each generated ``#include`` after the IDL's),
a C++ node written against Debian's Fast DDS 2.9 (``peer/src``) and the Fast DDS XML
profile it runs with. The build (``fastddsgen -typeros2``, then ``g++``) lands in a cache
folder named after the hash of those sources and of the installed Fast DDS libraries, so it
happens once per machine, and again only when something it is made of changes.

Loopback only, on both sides. The peer refuses to start without a profile, and
``peer/loopback_profile.xml`` gives it one UDPv4 transport whitelisted to 127.0.0.1, the
built-in transports (shared memory included) off, unicast discovery to 127.0.0.1 and no
multicast locator. :data:`CYCLONE_LOOPBACK` tells Cyclone DDS to use the 127.0.0.1
interface only, multicast off, the one peer 127.0.0.1, so that it announces and sends to
127.0.0.1 only. Checked by hand with ``ss -uanp`` during a run: every socket of the peer is
bound to 127.0.0.1 and none joins a multicast group; Cyclone DDS binds its sending socket
to 127.0.0.1 but, whatever its configuration, its unicast receiving sockets to 0.0.0.0
(``ddsi_udp.c`` always binds those to any address), so it listens on every interface
while it only ever talks to 127.0.0.1.
"""

from __future__ import annotations

import ctypes.util
import fcntl
import hashlib
import os
import re
import shutil
import signal
import socket
import subprocess
import tempfile
from pathlib import Path

from tests.system_packages import require

PEER_SOURCES = Path(__file__).parent / "peer"
PROFILE = PEER_SOURCES / "loopback_profile.xml"
# the topics' own types: fastddsgen also generates every type they include
TOPIC_TYPES = ("Twist", "Odometry", "LaserScan", "PoseStamped", "TFMessage", "Clock")
FAST_DDS_LIBRARIES = ("fastrtps", "fastcdr")

CYCLONE_LOOPBACK = (
    '<CycloneDDS><Domain Id="any">'
    '<General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>'
    "<AllowMulticast>false</AllowMulticast></General>"
    '<Discovery><Peers><Peer address="127.0.0.1"/></Peers>'
    # a fixed port per participant, so that unicast discovery can find it
    "<ParticipantIndex>auto</ParticipantIndex>"
    "<MaxAutoParticipantIndex>20</MaxAutoParticipantIndex></Discovery>"
    "</Domain></CycloneDDS>"
)
# ROS_DOMAIN_IDs 201..232: above the 1..200 the other ROS 2 tests take, below the highest
# domain whose RTPS ports (7400 + 250 d + ...) still fit in 16 bits
_FIRST_DOMAIN, _DOMAINS_PER_WORKER, _WORKERS = 201, 4, 8
_domains_taken = 0


def _digest() -> str:
    """The hash of everything the binary is made of: sources, profile, Fast DDS's version."""
    digest = hashlib.sha256()
    for path in sorted(p for p in PEER_SOURCES.rglob("*") if p.is_file()):
        digest.update(str(path.relative_to(PEER_SOURCES)).encode() + b"\0" + path.read_bytes())
    for library in FAST_DDS_LIBRARIES:  # e.g. libfastrtps.so.2.9: the soname has the version
        digest.update(str(ctypes.util.find_library(library)).encode())
    return digest.hexdigest()[:16]


def _cache_root() -> Path:
    return Path(tempfile.gettempdir()) / "mimics-tests" / "fastdds-peer"


def build_peer() -> Path:
    """The peer's binary, built unless the cache already holds this version of it."""
    require("compiler")
    require("fastdds")
    root = _cache_root()
    binary = root / _digest() / "mimics_ros2_peer"
    if binary.exists():
        return binary
    root.mkdir(parents=True, exist_ok=True)
    with open(root / ".lock", "w") as lock:  # xdist workers: one builds, the others wait
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not binary.exists():
            _build_into(binary.parent)
    return binary


def _build_into(folder: Path) -> None:
    building = Path(tempfile.mkdtemp(prefix=".build-", dir=folder.parent))
    try:
        generated = building / "generated"
        generated.mkdir()
        _run(["fastddsgen", "-cs", "-typeros2", "-replace", "-d", str(generated),
              *(f"{name}.idl" for name in TOPIC_TYPES)], cwd=PEER_SOURCES / "idl")
        # the generated sources as one translation unit: Fast DDS's headers parsed once, not
        # once per file (about 6 s of compiling instead of 35)
        all_types = building / "all_types.cxx"
        all_types.write_text("".join(f'#include "{path.name}"\n'
                                     for path in sorted(generated.glob("*.cxx"))))
        _run([shutil.which("g++") or "g++", "-std=c++17", "-O1", "-Wall",
              f"-I{generated}", f"-I{PEER_SOURCES / 'src'}", "-o",
              str(building / "mimics_ros2_peer"), str(PEER_SOURCES / "src" / "peer.cpp"),
              str(all_types), "-lfastrtps", "-lfastcdr", "-pthread"], cwd=building)
        building.rename(folder)  # whole or not at all
    finally:
        shutil.rmtree(building, ignore_errors=True)


def _run(command: list[str], cwd: Path) -> None:
    done = subprocess.run(command, cwd=cwd, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"{command[0]} failed ({done.returncode}):\n"
                           f"{done.stdout[-3000:]}\n{done.stderr[-3000:]}")


def _ports_free(domain: int) -> bool:
    """Whether the discovery ports of participants 0 and 1 on ``domain`` are unused."""
    for participant in (0, 1):
        port = 7400 + 250 * domain + 10 + 2 * participant
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as probe:
            try:
                probe.bind(("127.0.0.1", port))
            except OSError:
                return False
    return True


def next_domain() -> int:
    """A ROS_DOMAIN_ID of this test's own: xdist worker gwN takes 201 + 4 N .. 204 + 4 N,
    in turn, skipping a domain whose discovery ports something else holds."""
    global _domains_taken
    worker = os.environ.get("PYTEST_XDIST_WORKER", "gw0").removeprefix("gw")
    first = _FIRST_DOMAIN + (int(worker) % _WORKERS if worker.isdigit() else 0) * \
        _DOMAINS_PER_WORKER
    for _ in range(_DOMAINS_PER_WORKER):
        domain = first + _domains_taken % _DOMAINS_PER_WORKER
        _domains_taken += 1
        if _ports_free(domain):
            return domain
    raise RuntimeError(f"no free DDS domain in {first}..{first + _DOMAINS_PER_WORKER - 1}")


def peer_environment(domain: int) -> dict[str, str]:
    """The environment of a DDS process on ``domain``, loopback only for Fast DDS and Cyclone."""
    env = {**os.environ, "ROS_DOMAIN_ID": str(domain), "CYCLONEDDS_URI": CYCLONE_LOOPBACK,
           "FASTRTPS_DEFAULT_PROFILES_FILE": str(PROFILE)}
    # settings that would send Fast DDS elsewhere (a discovery server, another profile file)
    for name in ("ROS_DISCOVERY_SERVER", "FASTDDS_ENVIRONMENT_FILE",
                 "RMW_FASTRTPS_USE_QOS_FROM_XML", "FASTDDS_DEFAULT_PROFILES_FILE"):
        env.pop(name, None)
    return env


def start_peer(binary: Path, domain: int, robots: int, *options: str,
               timeout: float = 60) -> subprocess.Popen[str]:
    """Start the peer on ``domain`` for ``robots`` robots; ``options`` as
    ``--steps S``, ``--echo``, ``--echo-count K``, ``--echo-topics a,b``."""
    command = [str(binary), "--robots", str(robots), "--domain", str(domain),
               "--timeout", str(int(timeout)), *options]
    return subprocess.Popen(command, env=peer_environment(domain), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)


def finish_peer(peer: subprocess.Popen[str], timeout: float = 30) -> tuple[int, str, str]:
    """Wait for the peer (killed after ``timeout`` s): its exit status, stdout and stderr."""
    try:
        out, err = peer.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        peer.kill()
        out, err = peer.communicate()
        err += f"\n(killed after {timeout} s)"
    return peer.returncode, out, err


def stop_peer(peer: subprocess.Popen[str], timeout: float = 30) -> tuple[int, str, str]:
    """SIGTERM: the peer ends as if done (status 0, report printed), then :func:`finish_peer`."""
    if peer.poll() is None:
        peer.send_signal(signal.SIGTERM)
    return finish_peer(peer, timeout)


def run_peer(binary: Path, domain: int, robots: int, *options: str,
             timeout: float = 60) -> tuple[int, str, str]:
    """Run the peer to its end: its exit status, stdout and stderr."""
    return finish_peer(start_peer(binary, domain, robots, *options, timeout=timeout),
                       timeout + 15)


def final_poses(stdout: str) -> dict[int, tuple[float, float, float, float]]:
    """The peer's last lines ``robot i final x y goal gx gy``: {i: (x, y, gx, gy)}."""
    poses = {}
    for line in stdout.splitlines():
        words = line.split()
        if len(words) == 8 and words[0] == "robot" and words[2] == "final" and words[5] == "goal":
            poses[int(words[1])] = (float(words[3]), float(words[4]), float(words[6]),
                                    float(words[7]))
    return poses


def answered(stderr: str) -> dict[int, tuple[int, int]]:
    """The peer's count per robot: {i: (odometry messages, Twists sent)}."""
    return {int(i): (int(odometry), int(twists)) for i, odometry, twists in re.findall(
        r"robot (\d+) answered (\d+) odometry messages with (\d+) twists", stderr)}
