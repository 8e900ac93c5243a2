"""Small systems assembled inside the tests, independent of the catenary discretisation."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pytest
import scipy.sparse as sp


@dataclass(frozen=True)
class StringModel:
    """Lumped-mass tensioned string with both ends fixed (interior nodes only).

    Attributes
    ----------
    mass, stiffness : scipy.sparse.csr_matrix
        M [kg] and K [N/m] over the interior nodes.
    x : numpy.ndarray
        Node positions along the string. [m]
    element_length : float
        [m]
    """

    mass: sp.csr_matrix
    stiffness: sp.csr_matrix
    x: np.ndarray
    element_length: float


def build_string(*, tension: float, mass_per_length: float, length: float, element_length: float) -> StringModel:
    """Assemble a tensioned string of elements k = T/h with lumped masses ρh at the nodes.

    Parameters
    ----------
    tension : float
        [N]
    mass_per_length : float
        [kg/m]
    length : float
        Distance between the fixed ends. [m]
    element_length : float
        Target element length; rounded so that whole elements fit. [m]
    """
    n_elements = round(length / element_length)
    h = length / n_elements
    n = n_elements - 1
    k = tension / h
    stiffness = sp.diags([-k * np.ones(n - 1), 2 * k * np.ones(n), -k * np.ones(n - 1)], [-1, 0, 1], format="csr")
    mass = sp.diags(mass_per_length * h * np.ones(n), format="csr")
    return StringModel(mass=mass, stiffness=stiffness, x=h * np.arange(1, n + 1), element_length=h)


@pytest.fixture
def tensioned_string():
    """The :func:`build_string` builder."""
    return build_string
