#!/bin/sh
# roslaunch's way into `mimics ros`: drops the arguments roslaunch adds to every node
# (__name:=..., __log:=...), which mimics does not take, and runs the mimics that wrote
# this file (`mimics ros-files`).
for arg do
  shift
  case "$arg" in
    __*:=*) ;;
    *) set -- "$@" "$arg" ;;
  esac
done
exec @PYTHON@ -m mimics ros "$@"
