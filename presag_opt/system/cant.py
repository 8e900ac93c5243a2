"""Cant: the track plane tilted on a curve, and the pantograph with it.

On a curve with cant D (the outer rail raised by D over the rail-centre distance s) the vehicle and its
pantograph tilt by θ = asin(D/s) towards the inside of the curve. A survey measures the contact wire as
the pantograph sees it: the stagger y' from the axis perpendicular to the track plane at the centre of
the track, the height z' perpendicular to the track plane (the convention of public technical
regulations, e.g. Bane NOR's: stagger measured from a target axis perpendicular to the track plane).
The static model works in the level frame (gravity vertical): the lateral offset y from the vertical
through the centre of the track at rail level and the height z above that point, + to the left. With
s_R = +1 on a left-hand curve (the right rail raised), −1 on a right-hand one, the track frame is the
level frame turned by s_R·θ about the track centre line:

    y = y'·cos θ + s_R·z'·sin θ,        z = z'·cos θ − s_R·y'·sin θ,

so a wire straight above the pantograph's axis at height h lies h·D/s towards the inside of the curve
in the level frame (5.5 m above the rail with 100 mm of cant: 0.37 m). Heights are taken at the centre
of the track, so the vertical alignment is that of the track centre line.
"""

from __future__ import annotations

import math

RAIL_CENTRE_DISTANCE = 1.5
"""Distance between the running rails' centres that cant is given over on standard gauge (1435 mm gauge
plus a rail head). [m]"""

MAX_CANT = 0.2
"""Largest cant accepted. [m]"""


def level_frame(stagger: float, height: float, cant: float, direction: float) -> tuple[float, float]:
    """The level-frame lateral offset and height of a point given in the canted track frame.

    Parameters
    ----------
    stagger : float
        Lateral offset from the axis perpendicular to the track plane, + to the left. [m]
    height : float
        Height perpendicular to the track plane. [m]
    cant : float
        Cant D, the outer rail raised by it (≥ 0). [m]
    direction : float
        s_R: +1 on a left-hand curve, −1 on a right-hand one (0: no tilt). [-]
    """
    sin = direction * cant / RAIL_CENTRE_DISTANCE
    cos = math.sqrt(1.0 - sin * sin)
    return stagger * cos + height * sin, height * cos - stagger * sin


def track_frame(lateral: float, height: float, cant: float, direction: float) -> tuple[float, float]:
    """The canted track-frame stagger and height of a point given in the level frame (:func:`level_frame`'s
    inverse).

    Parameters
    ----------
    lateral : float
        Lateral offset from the vertical through the track centre, + to the left. [m]
    height : float
        Height above the track centre at rail level. [m]
    cant : float
        Cant D (≥ 0). [m]
    direction : float
        s_R: +1 on a left-hand curve, −1 on a right-hand one. [-]
    """
    sin = direction * cant / RAIL_CENTRE_DISTANCE
    cos = math.sqrt(1.0 - sin * sin)
    return lateral * cos - height * sin, height * cos + lateral * sin


def track_height(height: float, stagger: float, tilt: float) -> float:
    """The height perpendicular to the track plane of a point at level-frame height ``height`` whose stagger
    in the track frame is ``stagger``: z' = (z + s_R·y'·sin θ)/cos θ (from :func:`level_frame`). [m]

    Parameters
    ----------
    height : float
        Level-frame height above the track centre at rail level. [m]
    stagger : float
        Track-frame stagger, + to the left. [m]
    tilt : float
        s_R·D: the cant signed by the curve's direction (+ left-hand). [m]
    """
    sin = tilt / RAIL_CENTRE_DISTANCE
    return (height + stagger * sin) / math.sqrt(1.0 - sin * sin)
