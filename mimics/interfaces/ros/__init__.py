"""The live ROS 1 bridge: ``mimics ros`` runs a simulation as a ROS node.

A bridge is a set of small capabilities, one module each: ``clock``,
``odometry``, ``scans``, ``grid_map`` (the latched ``/map``), ``frames`` (tf2),
``goals``, ``commands`` (the ``cmd`` and ``cmd_vel`` subscriptions); every
topic and frame name comes from ``names`` (the ``mimics`` and ``stage`` name
sets), the odometer's ``odom`` frame and covariance from ``odometry_frame``
(plain NumPy); message conversion lives in one place (``conversion``), the map's rasterisation in
``occupancy``, the references' hand-over between ROS threads and the step in
``inbox`` and ``references``, the node's name, ROS arguments and private
parameters in ``node``, SIGINT and SIGTERM in ``stopping``, and ``bridge``
ties them to a run. What ROS
tools look for: ``parameters`` (``/use_sim_time``, the ``/mimics`` tree),
``services`` (pause, resume, step, reset), ``markers`` (``/mimics/markers``,
built by the export's marker functions) and ``launch_files`` (``mimics
ros-files``: the roslaunch package in ``files/``).

The transport-free core is shared with the ROS 2 bridge
(:mod:`mimics.interfaces.ros2`): ``bridge_core`` (lockstep, pace, the wait for
the nodes, resets), ``planar`` and ``readings`` (what each message carries),
``run_control`` (what the services do), ``inbox``, ``references``, ``names``,
``odometry_frame``, ``occupancy`` and ``stopping``; the modules that import
``rospy`` are ROS 1's transport.

ROS comes from Debian's packages in the system's dist-packages;
``system_ros`` makes them importable (see ``docs/how-to/ros.md``). Import
``system_ros`` (or call :func:`system_ros.require_ros`) before the modules
that import ``rospy``.
"""
