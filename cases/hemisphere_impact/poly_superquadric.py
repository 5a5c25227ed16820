"""Closed-form volume, centroid and inertia of a poly-superquadric (book Eqs. 3.17 to 3.25) in
its octant frame, for the validation scripts: the eight octant pieces' moments
J(p, q, r) = B((p+1)/n2, (q+1)/n2) B((r+1)/n1, (p+q+2)/n1 + 1) / (n1 n2 (p+q+2)) summed with
their semi-axes (Zhao & Zhao 2019; Jaklic et al. 2000 for the Beta integrals)."""
import math

import numpy as np


def beta(p, q):
    return math.exp(math.lgamma(p) + math.lgamma(q) - math.lgamma(p + q))


def octant_moment(p, q, r, n1, n2):
    return (beta((p + 1) / n2, (q + 1) / n2) * beta((r + 1) / n1, (p + q + 2) / n1 + 1)
            / (n1 * n2 * (p + q + 2)))


def mass_properties(plus, minus, n1, n2, density):
    """Mass (kg), centroid from the origin O0 (m) and inertia tensor about the centroid (kg m^2),
    octant frame."""
    plus, minus = np.asarray(plus, float), np.asarray(minus, float)
    sums = [plus + minus, plus ** 2 - minus ** 2, plus ** 3 + minus ** 3]  # S0, S1, S2 per axis

    def moment(powers):
        value = octant_moment(*powers, n1, n2)
        for axis, power in enumerate(powers):
            value *= sums[power][axis]
        return value

    volume = moment((0, 0, 0))
    first = np.array([moment(tuple(int(a == k) for a in range(3))) for k in range(3)])
    second = np.empty((3, 3))
    for a in range(3):
        for b in range(3):
            powers = [0, 0, 0]
            powers[a] += 1
            powers[b] += 1
            second[a, b] = moment(tuple(powers))
    centroid = first / volume
    central = second - volume * np.outer(centroid, centroid)
    inertia = density * (np.trace(central) * np.eye(3) - central)
    return density * volume, centroid, inertia
