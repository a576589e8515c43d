"""The live view: drawn at exactly the paper's representation times, headless, or not at all."""

from types import SimpleNamespace

import numpy as np
import pytest

from mimics.engine.state import Status, TypeArrays, WorldState
from mimics.interfaces.live_view import (
    LiveView,
    TrailBuffer,
    has_display,
    make_live_view,
)
from mimics.world.errors import MimicsError
from mimics.world.limits import steps_for
from mimics.world.maps import Map
from mimics.world.robot_types import RangerSpec, RobotType
from mimics.world.scenario import Scenario, Settings

SEEING = RobotType("seeing", width=0.8, length=1.2, kv=1.0, kw=1.0, tau_v=0.5, tau_w=0.2,
                   ranger=RangerSpec("test", fov=np.pi, beams=5, range=3.0))


class ScriptedSim:
    """Just what an observer reads of a Simulation, with robots driving at 0.5 m/s."""

    def __init__(self, duration: float, dt: float = 0.1) -> None:
        rows = [[1.0, 1.0, 0.0, 0.0, 9.0, 1.0], [1.0, 4.0, 0.0, 0.0, 9.0, 4.0]]
        self.scenario = Scenario.from_matrix(rows, Map.box(12.0, 6.0), SEEING,
                                             settings=Settings(dt=dt, time_limit=duration),
                                             name="scripted")
        self.types = TypeArrays.from_scenario(self.scenario)
        self.state = WorldState.from_scenario(self.scenario, 5)
        self.state.scan[:] = 2.0
        self.controller = SimpleNamespace(name="drive")
        self.seed = 3
        self.max_steps = steps_for(duration, dt)

    def run(self, *observers) -> None:
        for o in observers:
            o.on_start(self)
        dt = self.scenario.settings.dt
        while self.state.step < self.max_steps:
            self.state.pose[:, 0] += 0.5 * dt
            self.state.step += 1
            self.state.time = self.state.step * dt
            if self.state.time > 2.0:
                self.state.status[1] = Status.COLLIDED
            for o in observers:
                o.on_step(self)
        for o in observers:
            o.on_end(self, None)


@pytest.mark.parametrize(("mode", "duration", "expected"), [
    ("1s", 3.5, [0.0, 1.0, 2.0, 3.0, 3.5]),
    ("10s", 21.8, [0.0, 10.0, 20.0, 21.8]),
    ("10s", 20.0, [0.0, 10.0, 20.0]),
    ("step", 0.5, [0.0, 0.1, 0.2, 0.3, 0.4, 0.5]),
])
def test_frames_are_drawn_at_the_representation_times(mode, duration, expected) -> None:
    view = LiveView(mode, offscreen=True)
    ScriptedSim(duration).run(view)
    np.testing.assert_allclose(view.drawn_times, expected, atol=1e-9)


def test_frames_are_drawn_at_whole_seconds_whatever_the_step() -> None:
    view = LiveView("1s", offscreen=True)
    ScriptedSim(3.0, dt=0.3).run(view)  # 0.3 s steps cross each second between two steps
    np.testing.assert_allclose(view.drawn_times, [0.0, 1.2, 2.1, 3.0], atol=1e-9)


def test_offscreen_frames_show_the_robots_in_their_state_colours() -> None:
    frames: list[tuple[float, np.ndarray]] = []
    view = LiveView("1s", offscreen=True, beams_of=0,
                    on_frame=lambda t, rgb: frames.append((t, rgb.copy())))
    sim = ScriptedSim(3.0)
    sim.run(view)
    assert [t for t, _ in frames] == view.drawn_times
    renderer = view.renderer
    assert renderer is not None
    image = frames[-1][1]
    np.testing.assert_array_equal(image, view.frame())
    for robot, name in ((0, "active"), (1, "collided")):
        col, row = renderer.world_to_pixel(sim.state.pose[robot:robot + 1, :2])[0]
        assert tuple(image[int(row), int(col)]) == renderer.color_of(name)


def test_off_costs_nothing() -> None:
    assert make_live_view("off") is None
    view = LiveView("off", offscreen=True)
    ScriptedSim(1.0).run(view)
    assert view.drawn_times == [] and view.renderer is None


def test_without_a_display_the_view_says_so_once_and_does_nothing(monkeypatch, capsys) -> None:
    monkeypatch.delenv("DISPLAY", raising=False)
    monkeypatch.delenv("WAYLAND_DISPLAY", raising=False)
    assert not has_display()
    assert make_live_view("1s") is None
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--video" in err[0]
    view = LiveView("step")
    ScriptedSim(0.3).run(view)
    assert view.drawn_times == []
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_bad_modes_and_robots_are_errors() -> None:
    with pytest.raises(MimicsError, match="step, 1s, 10s, off"):
        make_live_view("2s")
    with pytest.raises(MimicsError):
        LiveView("fast")
    with pytest.raises(MimicsError, match="robot 7"):
        ScriptedSim(1.0).run(LiveView("1s", offscreen=True, beams_of=7))


def test_trail_buffer_keeps_the_last_positions_oldest_first() -> None:
    trail = TrailBuffer(n=1, points=3, every=2)
    for k in range(7):
        trail.push(np.array([[float(k), 0.0]]))
    segments = trail.segments(np.array([[9.0, 0.0]]))
    assert segments.shape == (1, 4, 2)
    assert segments[0, :, 0].tolist() == [2.0, 4.0, 6.0, 9.0]


def test_the_engine_calls_the_view_at_each_simulated_second() -> None:
    from mimics.algorithms import go_to_goal
    from mimics.engine.simulation import Simulation
    from mimics.scenarios.line import scenario

    view = LiveView("1s", offscreen=True, beams_of=1)
    sim = Simulation(scenario(robots=3), go_to_goal, seed=1, time_limit=2.5, observers=[view])
    sim.run()
    np.testing.assert_allclose(view.drawn_times, [0.0, 1.0, 2.0, 2.5], atol=1e-9)
    assert view.frame().shape[2] == 3
