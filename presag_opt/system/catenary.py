"""Catenary system models: the span layout with its pre-sag, and the tension section.

The parts they are built from (wires, droppers, steady arms, supports, damping) are in
:mod:`presag_opt.system.components`.

All values are SI inside these classes (N, m, kg, N/m, N·m²); model files and the command line may
use kN, mm, ‰ and are converted on loading. Every class is frozen and keyword-only, and checks its
fields on construction (see :mod:`presag_opt.system.quantity`).

Sign convention: x along the track, y lateral (positive to the left looking in +x), z up.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from presag_opt.errors import ModelError
from presag_opt.system.components import (
    Damping,
    Droppers,
    PinSupport,
    Provenance,
    SpringSupport,
    SteadyArm,
    Wire,
)
from presag_opt.system.masts import MastGeometry
from presag_opt.system.quantity import quantity, validate_fields
from presag_opt.system.stitch import StitchWire


@dataclass(frozen=True, kw_only=True)
class SpanLayout:
    """Span lengths of a tension section and, optionally, a curve radius per span.

    Attributes
    ----------
    span_lengths : tuple of float
        Length of each span, in order. [m]
    curve_radii : tuple of float or None
        Horizontal curve radius of each span, positive curving to the left (+y), negative to the
        right, 0 for straight track. [m]
    label : str
        What the list is (e.g. that it is a stand-in for a list not published).
    """

    span_lengths: tuple[float, ...] = quantity("length", 5.0, 120.0)
    curve_radii: tuple[float, ...] | None = quantity("length", -1e6, 1e6, default=None, allow_none=True)
    label: str = ""

    def __post_init__(self) -> None:
        object.__setattr__(self, "span_lengths", tuple(float(v) for v in self.span_lengths))
        validate_fields(self)
        if len(self.span_lengths) < 3:
            raise ModelError(
                f"layout.span_lengths has {len(self.span_lengths)} spans; a section needs at least 3 "
                "(the central span is analysed away from the terminations)"
            )
        if self.curve_radii is not None:
            radii = tuple(float(v) for v in self.curve_radii)
            object.__setattr__(self, "curve_radii", radii)
            if len(radii) != len(self.span_lengths):
                raise ModelError(
                    f"layout.curve_radii has {len(radii)} values but there are {len(self.span_lengths)} spans"
                )
            for i, r in enumerate(radii):
                if r != 0.0 and abs(r) < 100.0:
                    raise ModelError(
                        f"layout.curve_radii[{i}] = {r:g} m: a curve radius must be 0 (straight) or at least 100 m in size"
                    )

    @property
    def n_spans(self) -> int:
        """Number of spans."""
        return len(self.span_lengths)

    @property
    def central_span(self) -> int:
        """Index (from 0) of the span analysed by default: the middle one (the later of two)."""
        return self.n_spans // 2

    @property
    def radii(self) -> tuple[float, ...]:
        """Curve radius per span, 0 where straight. [m]"""
        return self.curve_radii if self.curve_radii is not None else (0.0,) * self.n_spans


@dataclass(frozen=True, kw_only=True)
class Catenary:
    """A simple catenary tension section.

    Attributes
    ----------
    name : str
        Display name.
    contact_wire, messenger_wire : Wire
        The two wires.
    droppers : Droppers
        Dropper rule and properties.
    contact_wire_support : SteadyArm or SpringSupport
        How the contact wire is held at each mast.
    messenger_wire_support : PinSupport or SpringSupport
        How the messenger wire is held at each mast.
    layout : SpanLayout
        Spans of the section.
    contact_wire_height : float
        Contact-wire height at the supports above the rail. [m]
    system_height : float
        Messenger above contact wire at the supports (encumbrance). [m]
    stagger : float
        Lateral offset of the contact wire at the masts, alternating in sign. [m]
    presag_rel : float
        Pre-sag as a fraction of span length (0.0005 = 0.5 ‰); each span's mid-span pre-sag is
        presag_rel times its length (Swedish practice): the contact wire lies on a parabola through
        the droppers. With a ``presag_profile`` it is only the profile's label (its mean mid-span
        depth over span length, see :meth:`with_presag_profile`). [-]
    presag_profile : tuple of tuple of float, or None
        Any other pre-sag: the depth of the contact wire below its support level at every dropper,
        one tuple per span (droppers in order along the track), each within 0–5 ‰ of its span
        length; between the droppers and the masts the target is the straight line through them.
        None (the default): the parabola of ``presag_rel``. [m]
    damping : Damping or None
        Structural damping for dynamic analysis.
    masts : MastGeometry or None
        Per-mast signed stagger, heights and steady-arm type (a surveyed section); None: the scalar
        ``stagger`` (alternating), ``contact_wire_height`` and ``system_height`` at every mast, and
        pull-off arms.
    stitch_wire : StitchWire or None
        A stitch wire at every inner mast (a stitched catenary); None: a simple catenary.
    provenance : dict
        Dotted model-file key -> :class:`Provenance`.
    """

    name: str
    contact_wire: Wire
    messenger_wire: Wire
    droppers: Droppers
    contact_wire_support: SteadyArm | SpringSupport
    messenger_wire_support: PinSupport | SpringSupport
    layout: SpanLayout
    contact_wire_height: float = quantity("length", 3.0, 8.0)
    system_height: float = quantity("length", 0.2, 4.0)
    stagger: float = quantity("length", 0.0, 0.5, default=0.0)
    presag_rel: float = quantity("ratio", 0.0, 5.0, display="‰", default=0.0)
    presag_profile: tuple[tuple[float, ...], ...] | None = None
    damping: Damping | None = None
    masts: MastGeometry | None = None
    stitch_wire: StitchWire | None = None
    provenance: dict[str, Provenance] = field(default_factory=dict, compare=False, repr=False)

    def __post_init__(self) -> None:
        validate_fields(self)
        shortest = min(self.layout.span_lengths)
        positions = self.droppers.positions_in_span(shortest)
        if len(positions) < 2:
            raise ModelError(f"droppers: a span of {shortest:g} m gets fewer than two droppers")
        springs = isinstance(self.contact_wire_support, SpringSupport) or isinstance(
            self.messenger_wire_support, SpringSupport
        )
        if springs and any(self.layout.radii):
            raise ModelError(
                "layout.curve_radii: spring supports model straight track only; use a steady_arm contact-wire "
                "support and a pin messenger-wire support on curves"
            )
        if self.masts is not None and self.masts.n_masts != self.layout.n_spans + 1:
            raise ModelError(
                f"masts: {self.masts.n_masts} masts given for {self.layout.n_spans} spans (needs {self.layout.n_spans + 1})"
            )
        if (isinstance(self.contact_wire_support, SteadyArm) and self.masts is None and self.stagger == 0.0
                and not any(self.layout.radii)):
            raise ModelError(
                "stagger = 0 m on straight track leaves a steady arm without lateral pull (it would have no "
                "vertical stiffness); give a stagger in (0, 0.5] m or use a spring support"
            )
        if self.presag_profile is not None:
            self._check_presag_profile()
        if self.stitch_wire is not None:
            self._check_stitch_wire()

    def _check_stitch_wire(self) -> None:
        """The stitch wire's clamps must lie between the mast and the first (last) dropper of every span,
        and its tension be at most half the messenger wire's."""
        half = 0.5 * self.stitch_wire.length
        most = 0.5 * self.messenger_wire.tension
        if self.stitch_wire.tension > most:
            raise ModelError(
                f"stitch_wire.tension = {self.stitch_wire.tension * 1e-3:g} kN is outside the valid range (0, "
                f"{most * 1e-3:g}] kN: at most half the messenger-wire tension, which between the stitch wire's "
                "clamps carries its own tension less the stitch wire's"
            )
        n = self.layout.n_spans
        if self.stitch_wire.masts is not None and self.stitch_wire.masts[-1] > n - 1:
            raise ModelError(f"stitch_wire.masts = {list(self.stitch_wire.masts)}: mast {self.stitch_wire.masts[-1]} is "
                             f"not an inner mast of the {n} spans (valid: 1 to {n - 1})")
        for s, length in enumerate(self.layout.span_lengths):
            drops = self.droppers.positions_in_span(length)
            ends = [d for d, m in ((drops[0], s), (length - drops[-1], s + 1)) if self.stitch_wire.at_mast(m, n)]
            if not ends:
                continue
            room = min(ends)
            if half > room + 1e-9:
                raise ModelError(
                    f"stitch_wire.length = {self.stitch_wire.length:g} m is outside the valid range (0, {2 * room:g}] m "
                    f"for span {s + 1}: its clamps must lie between the mast and the first droppers "
                    f"({drops[0]:g} m and {length - drops[-1]:g} m from the masts)"
                )

    def _check_presag_profile(self) -> None:
        """Normalise the profile to tuples of floats; one depth per dropper of each span, each within
        0–5 ‰ of its span length (the range of ``presag_rel``)."""
        profile = tuple(tuple(float(d) for d in span) for span in self.presag_profile)
        object.__setattr__(self, "presag_profile", profile)
        lengths = self.layout.span_lengths
        if len(profile) != len(lengths):
            raise ModelError(f"presag_profile has {len(profile)} spans but the layout has {len(lengths)}")
        high = Catenary.__dataclass_fields__["presag_rel"].metadata["quantity"]["high"] * 1e-3
        for s, (depths, length) in enumerate(zip(profile, lengths)):
            count = len(self.droppers.positions_in_span(length))
            if len(depths) != count:
                raise ModelError(f"presag_profile[{s}] has {len(depths)} depths but span {s} has {count} droppers")
            for i, depth in enumerate(depths):
                if not 0.0 <= depth <= high * length:  # also refuses NaN
                    raise ModelError(
                        f"presag_profile[{s}][{i}] = {depth * 1e3:g} mm is outside the valid range "
                        f"[0, {high * length * 1e3:g}] mm (0–{high * 1e3:g} ‰ of the {length:g} m span)"
                    )

    def mast_stagger(self) -> np.ndarray:
        """Signed stagger at every mast, + to the left (alternating ``±stagger`` without ``masts``). [m]"""
        if self.masts is not None:
            return np.asarray(self.masts.stagger)
        return self.stagger * np.where(np.arange(self.layout.n_spans + 1) % 2 == 0, 1.0, -1.0)

    def mast_contact_wire_height(self) -> np.ndarray:
        """Contact-wire height above the rail at every mast. [m]"""
        if self.masts is not None:
            return np.asarray(self.masts.contact_wire_height)
        return np.full(self.layout.n_spans + 1, self.contact_wire_height)

    def mast_system_height(self) -> np.ndarray:
        """System height (messenger above contact wire) at every mast. [m]"""
        if self.masts is not None:
            return np.asarray(self.masts.system_height)
        return np.full(self.layout.n_spans + 1, self.system_height)

    def mast_push_off(self) -> np.ndarray:
        """True at every mast whose steady arm is a push-off arm (in compression)."""
        if self.masts is not None:
            return np.asarray(self.masts.push_off, dtype=bool)
        return np.zeros(self.layout.n_spans + 1, dtype=bool)

    def support_line(self, span: int, positions: np.ndarray) -> np.ndarray:
        """Height of the straight line between the contact-wire supports of a span. [m]

        The pre-sag (:meth:`presag_depth`) is measured below this line.

        Parameters
        ----------
        span : int
            Span, from 0. [-]
        positions : ndarray
            Distances from the span's first mast, within [0, l]. [m]
        """
        heights = self.mast_contact_wire_height()
        t = np.asarray(positions, dtype=float) / self.layout.span_lengths[span]
        return heights[span] + (heights[span + 1] - heights[span]) * t

    def presag_of_span(self, span: int) -> float:
        """Mid-span pre-sag of span ``span`` (from 0). [m]

        Parameters
        ----------
        span : int
            Span, from 0. [-]
        """
        return self.presag_rel * self.layout.span_lengths[span]

    def with_presag(self, presag_rel: float) -> Catenary:
        """Copy with a parabolic pre-sag of relative depth ``presag_rel`` (any profile dropped). [-]

        Parameters
        ----------
        presag_rel : float
            Relative pre-sag S_rel (mid-span depth over span length). [-]
        """
        return dataclasses.replace(self, presag_rel=presag_rel, presag_profile=None)

    def with_presag_profile(self, depths) -> Catenary:
        """Copy with the contact wire at given depths below its support level at every dropper.

        Parameters
        ----------
        depths : sequence of sequence of float
            One sequence per span, one depth per dropper of that span (see :attr:`presag_profile`). [m]

        Returns
        -------
        Catenary
            With :attr:`presag_profile` set and :attr:`presag_rel` the profile's mean mid-span depth
            over span length (a label; the geometry is the profile).
        """
        profile = tuple(tuple(float(d) for d in span) for span in depths)
        shaped = dataclasses.replace(self, presag_profile=profile)  # checks the profile
        lengths = self.layout.span_lengths
        middle = [float(shaped.presag_depth(s, np.array([0.5 * length]))[0]) / length for s, length in enumerate(lengths)]
        return dataclasses.replace(shaped, presag_rel=float(np.mean(middle)))

    def presag_depth(self, span: int, positions: np.ndarray) -> np.ndarray:
        """Target depth of the contact wire below its support level in a span. [m]

        The parabola 4·S·t(1 − t), S = presag_rel·l, t = x/l; with a :attr:`presag_profile`, the
        straight lines through the masts (depth 0) and the profile's depths at the droppers.

        Parameters
        ----------
        span : int
            Span, from 0. [-]
        positions : ndarray
            Distances from the span's first mast, within [0, l]. [m]
        """
        length = self.layout.span_lengths[span]
        x = np.asarray(positions, dtype=float)
        if self.presag_profile is None:
            t = x / length
            return 4.0 * (self.presag_rel * length) * t * (1.0 - t)
        drops = self.droppers.positions_in_span(length)
        return np.interp(x, np.concatenate([[0.0], drops, [length]]),
                         np.concatenate([[0.0], self.presag_profile[span], [0.0]]))

    def with_layout(self, layout: SpanLayout) -> Catenary:
        """Copy with another span layout."""
        return dataclasses.replace(self, layout=layout)
