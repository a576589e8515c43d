"""Where each built-in robot type's noise figures come from: makers' datasheets and
Stage's defaults, cited by ``mimics robot show TYPE``."""

from __future__ import annotations

_ACCURACY_AS_SIGMA = "the maker's accuracy figure taken as one standard deviation"
_STAGE_ODOMETRY_SOURCE = ("odometry: Stage's position model default odom_error [0.03 0.03 0 0.05] "
                          "(rtv.github.io/Stage, position model), as 0.03 m per m and 0.05 rad "
                          "per rad (Stage draws it once per run as a scale error; here per step)")

NOISE_SOURCES: dict[str, str] = {
    "Pioneer3AT": ("ranger: Hokuyo UTM-30LX specifications (accuracy +-30 mm at 0.1-10 m, "
                   f"+-50 mm at 10-30 m): sigma 0.03 m, {_ACCURACY_AS_SIGMA}; "
                   f"{_STAGE_ODOMETRY_SOURCE}"),
    "Pioneer2DX": ("ranger: SICK LMS200 Technical Description (typical accuracy +-15 mm, mm "
                   f"mode, up to 8 m): sigma 0.015 m, {_ACCURACY_AS_SIGMA}; "
                   f"{_STAGE_ODOMETRY_SOURCE}"),
    "Swarmbot": ("ranger: as the SICK LMS200 (typical accuracy +-15 mm): sigma 0.015 m; "
                 f"{_STAGE_ODOMETRY_SOURCE}"),
    "TurtleBot3Burger": ("ranger: ROBOTIS LDS-01 specifications in the TurtleBot3 e-Manual "
                         "(accuracy +-15 mm at 0.12-0.499 m, +-5% at 0.5-3.5 m): sigma "
                         "0.015 m; odometry: no published figure, none"),
    "e-puck": ("ranger: the infrared sensors give an intensity, not a distance: 3 mm is an "
               "assumed sigma (GCtronic publishes no distance accuracy); odometry: no "
               "published figure, none"),
    "Kobuki": ("ranger: Khoshelham and Elberink, 'Accuracy and resolution of Kinect depth "
               "data for indoor mapping applications', Sensors 12(2), 2012 (random error "
               "sigma = 1.425e-3 z^2 m for the same PrimeSense sensor as the Xtion): 0.0175 m at "
               "its 3.5 m range; odometry: no published figure, none"),
    "point": "no sensors, no noise",
}
"""Where each built-in type's noise figures come from (``mimics robot show TYPE``).
Positioning noise is zero for every type: none has a positioning sensor of its own."""
