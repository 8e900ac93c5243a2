"""The path model (presag_opt.robust.path): the form-found geometry is affine in the dropper targets."""

from __future__ import annotations

import numpy as np

from presag_opt.static.form_finding import dropper_height_sensitivity, form_find


def test_form_found_geometry_is_affine_in_the_dropper_targets(st98):
    # The Jacobian predicts the 70 mm geometry from the 30 mm one; the form-finding equations are
    # nearly linear in the heights, so 0.01 mm over a 40 mm change is a tight but fair bound.
    cat = st98.catenary
    disc = st98.discretisation
    lengths = np.asarray(cat.layout.span_lengths)[disc.dropper_span]
    t = disc.dropper_position / lengths
    new_rel = 70e-3 / 60.0
    other = form_find(cat.with_presag(new_rel))
    change = -(new_rel - cat.presag_rel) * lengths * 4 * t * (1 - t)
    predicted = st98.positions[:, 2] + dropper_height_sensitivity(st98) @ change
    assert np.abs(predicted[disc.cw_nodes] - other.positions[disc.cw_nodes, 2]).max() < 1e-5
