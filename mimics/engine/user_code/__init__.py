"""Calling the user's algorithm: what its code sees, how long it may take, how it fails.

The step (``mimics.engine.simulation``) calls the user's code through this folder's face:

* :func:`controller_from`, :class:`Controller` and its kinds (``controllers``): the
  algorithm contract (``step(robot)`` per robot or ``step(team)`` once), timing each call
  and turning a raise or a bad return into a :class:`UserFailure` naming its line;
* :class:`Robot` and :class:`Team` (``robot_view``): the read-only views a step receives,
  which hold mirrors and a link to the hub (``view_hub``), never the simulation;
* :class:`Watchdog`, :class:`StepTimeout` and :func:`watched_load` (``watchdog``): the
  wall-clock limit on a step and on loading the user's file;
* where in the user's code a failure happened (``failure_places``) and the audit hook
  that keeps grading workers' code away from the simulation (``guard``).

Everything here reads the simulation through the :class:`SimulationParts` protocol
(``world_access``), so nothing in this folder imports the step that calls it.
"""

from mimics.engine.user_code.controllers import (
    Controller,
    PerRobotController,
    TeamController,
    UserFailure,
    controller_from,
)
from mimics.engine.user_code.failure_places import (
    failure_place,
    first_line,
    is_user_file,
    shown_path,
    user_traceback,
)
from mimics.engine.user_code.guard import install_guard
from mimics.engine.user_code.robot_view import Robot, Team
from mimics.engine.user_code.view_hub import ViewHub, hub_of
from mimics.engine.user_code.watchdog import (
    LoadTimeout,
    StepTimeout,
    Watchdog,
    describe_timeout,
    watched_load,
)
from mimics.engine.user_code.world_access import SimulationParts

__all__ = ["Controller", "LoadTimeout", "PerRobotController", "Robot", "SimulationParts",
           "StepTimeout", "Team", "TeamController", "UserFailure", "ViewHub", "Watchdog",
           "controller_from", "describe_timeout", "failure_place", "first_line",
           "hub_of", "install_guard", "is_user_file", "shown_path", "user_traceback",
           "watched_load"]
