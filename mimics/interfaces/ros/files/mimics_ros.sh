#!/bin/sh
# roslaunch's way into `mimics ros` of the mimics that wrote this file (`mimics ros-files`).
# The arguments roslaunch adds (__name:=..., __log:=..., remaps from <remap>) are passed
# on: mimics honours them as a rospy node does.
exec @PYTHON@ -m mimics ros "$@"
