"""Importers that turn drawings and occupancy images into wall segments.

* :func:`import_svg`: SVG vector drawings (``svg.py``);
* :func:`import_raster`: PNG/PGM/BMP occupancy images (``raster.py``);
* :func:`stage_bitmap`: Stage floorplan bitmaps, with Stage's scaling (``raster.py``);
* :func:`import_ros_map`: ROS map_server YAML files (``ros.py``).

``mimics.world.map_files.load_map`` picks the right one from a file's suffix.
"""

from mimics.world.map_import.raster import import_raster, stage_bitmap
from mimics.world.map_import.ros import import_ros_map
from mimics.world.map_import.svg import import_svg

__all__ = ["import_raster", "import_ros_map", "import_svg", "stage_bitmap"]
