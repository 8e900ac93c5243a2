"""Per-mast geometry of a tension section: signed stagger, heights and steady-arm type at every mast.

A section built from a survey (:mod:`presag_opt.system.survey`) differs from mast to mast; a
section written by hand has one stagger (alternating), one contact-wire height and one system
height. :class:`MastGeometry` holds the per-mast values; a :class:`~presag_opt.system.catenary.Catenary`
without one uses its scalar fields at every mast.

Sign convention: stagger positive to the left looking towards increasing chainage (+y).
"""

from __future__ import annotations

from dataclasses import dataclass

from presag_opt.errors import ModelError

STEADY_ARM_TYPES = ("pull-off", "push-off")
"""Steady-arm types: a pull-off arm is in tension (its pivot lies away from the wire's pull), a
push-off arm in compression (its pivot lies on the side the wire pulls towards)."""

CONTACT_WIRE_HEIGHT_RANGE = (3.0, 8.0)
"""Valid contact-wire height above the rail at a mast. [m]"""

SYSTEM_HEIGHT_RANGE = (0.2, 4.0)
"""Valid system height (messenger above contact wire) at a mast. [m]"""

STAGGER_LIMIT = 0.5
"""Largest stagger the model accepts in size (a survey checks against its own, tighter setting). [m]"""


@dataclass(frozen=True, kw_only=True)
class MastGeometry:
    """Stagger, heights and steady-arm type at every mast of one section, in track order.

    Attributes
    ----------
    stagger : tuple of float
        Signed lateral offset of the contact wire from the track centre line, + to the left. [m]
    contact_wire_height : tuple of float
        Contact-wire height above the rail at each mast. [m]
    system_height : tuple of float
        Messenger wire above the contact wire at each mast. [m]
    push_off : tuple of bool
        True where the steady arm is a push-off arm (in compression), False for a pull-off arm.
    """

    stagger: tuple[float, ...]
    contact_wire_height: tuple[float, ...]
    system_height: tuple[float, ...]
    push_off: tuple[bool, ...]

    def __post_init__(self) -> None:
        for name in ("stagger", "contact_wire_height", "system_height"):
            object.__setattr__(self, name, tuple(float(v) for v in getattr(self, name)))
        object.__setattr__(self, "push_off", tuple(bool(v) for v in self.push_off))
        n = len(self.stagger)
        for name in ("contact_wire_height", "system_height", "push_off"):
            if len(getattr(self, name)) != n:
                raise ModelError(f"masts.{name} has {len(getattr(self, name))} values but masts.stagger has {n}")
        checks = (("stagger", (-STAGGER_LIMIT, STAGGER_LIMIT)), ("contact_wire_height", CONTACT_WIRE_HEIGHT_RANGE),
                  ("system_height", SYSTEM_HEIGHT_RANGE))
        for name, (low, high) in checks:
            for i, value in enumerate(getattr(self, name)):
                if not low <= value <= high:  # also refuses NaN
                    raise ModelError(f"masts.{name}[{i}] = {value:g} m is outside the valid range [{low:g}, {high:g}] m")

    @property
    def n_masts(self) -> int:
        """Number of masts (spans + 1). [-]"""
        return len(self.stagger)
