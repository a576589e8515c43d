"""Importers that turn drawings and occupancy images into wall segments.

* :func:`import_svg`: SVG vector drawings (``svg.py``);
* :func:`import_raster`: PNG/PGM/BMP occupancy images (``raster.py``);
* :func:`stage_bitmap`: Stage floorplan bitmaps, with Stage's scaling (``raster.py``);
* :func:`import_ros_map`: ROS map_server YAML files (``ros.py``).

``mimics.world.map_files.load_map`` picks the right one from a file's suffix.
Each is imported on first use (svgelements, PyYAML and scikit-image are not
needed by a run whose map is plain text or already in the map cache,
``cache.py``).
"""

from __future__ import annotations

from importlib import import_module
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from mimics.world.map_import.raster import import_raster, stage_bitmap
    from mimics.world.map_import.ros import import_ros_map
    from mimics.world.map_import.svg import import_svg

_HOMES = {"import_raster": "raster", "stage_bitmap": "raster", "import_ros_map": "ros",
          "import_svg": "svg"}
__all__ = ["import_raster", "import_ros_map", "import_svg", "stage_bitmap"]


def __getattr__(name: str) -> object:
    if name not in _HOMES:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(import_module(f"{__name__}.{_HOMES[name]}"), name)
