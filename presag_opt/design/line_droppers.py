"""The dropper schedule of a built section: every dropper as a crew cuts and hangs it.

Read off the built equilibrium (:func:`presag_opt.design.line.build_line`): the clamp-to-clamp
(unstretched) length, both wires' heights at the dropper, the contact wire's lateral position there
(:func:`~presag_opt.design.line_rules.lateral_offset`), the absolute chainage, and the cut length of the
system's dropper type (:class:`~presag_opt.system.dropper_type.DropperType`) rounded to the crew's step.
On a canted curve the lateral position and the heights are in the track frame, as the pantograph sees
them (:func:`~presag_opt.system.cant.track_height`, the cant varying linearly between the masts; the
messenger wire taken at the contact wire's stagger).
"""

from __future__ import annotations

import numpy as np

from presag_opt.design.line_results import DropperDesign
from presag_opt.design.line_rules import lateral_offset
from presag_opt.static.equilibrium import EquilibriumState
from presag_opt.system.cant import track_height
from presag_opt.system.catenary import Catenary
from presag_opt.system.dropper_type import DropperType
from presag_opt.system.survey import SurveySection


def section_droppers(state: EquilibriumState, built: Catenary, section: SurveySection, dropper_type: DropperType,
                     round_step: float) -> tuple[DropperDesign, ...]:
    """Every dropper of a built section, in track order.

    Parameters
    ----------
    state : EquilibriumState
        The section form-found at the pre-sag built.
    built : Catenary
        The section's model at that pre-sag.
    section : SurveySection
        The surveyed masts.
    dropper_type : DropperType
        The allowances of the dropper type.
    round_step : float
        The crew's cutting step (0: exact). [m]
    """
    disc = state.discretisation
    ids = [m.mast for m in section.masts]
    clamp = state.params.unstretched_length[disc.dropper_elements]
    cut = np.atleast_1d(dropper_type.cut_length(clamp, round_step))
    cw_nodes = disc.axial.node_a[disc.dropper_elements]
    mw_nodes = disc.axial.node_b[disc.dropper_elements]
    stitch = disc.stitch_dropper if disc.stitch_dropper is not None else np.zeros(len(clamp), dtype=bool)
    tilts = [d * m.cant for d, m in zip(section.cant_directions(), section.masts)]
    droppers, count = [], {}
    for k, (span, x) in enumerate(zip(disc.dropper_span, disc.dropper_position)):
        span = int(span)
        count[span] = count.get(span, 0) + 1
        a, b = section.masts[span], section.masts[span + 1]
        share = float(x) / (b.chainage - a.chainage)
        tilt = (1.0 - share) * tilts[span] + share * tilts[span + 1]  # cant varies linearly between masts
        lateral = float(lateral_offset(a, b, np.array([x]))[0])
        droppers.append(DropperDesign(
            section=section.section, span=span + 1, from_mast=ids[span], to_mast=ids[span + 1],
            dropper=count[span], position=float(x), length=float(clamp[k]),
            contact_wire_height=track_height(float(state.positions[cw_nodes[k], 2]), lateral, tilt),
            presag=float(built.presag_depth(span, np.array([x]))[0]), stitch=bool(stitch[k]),
            chainage=a.chainage + float(x),
            messenger_height=track_height(float(state.positions[mw_nodes[k], 2]), lateral, tilt),
            lateral=lateral, cut_length=float(cut[k])))
    return tuple(droppers)
