"""More known answers for the EKM core (ekm.kohonen), written against a mutant the known-answer suite let through
(docs/mutation.md)."""

import jax.numpy as jnp

from ekm.config import EKMConfig
from ekm.kohonen import winner


def test_priority_of_all_but_one_neuron_leaves_out_the_furthest_in_angle():
    """Eq. 4.4 with |A(α)| = N² - 1 = 3: the neuron furthest in angle does not compete, even though by Eq. 4.3
    it is the nearest. u = (0, 0.02 m); |Δα|/π = 0.095, 0.127, 0.159, 0.318; (Δd/d_scale)² = 0.766, 0.766,
    0.766, 0 — D² = 0.775, 0.782, 0.791, 0.101. Kills ``jnp.partition(dalpha, cfg.a_size + 1)`` (an index
    past the end when |A(α)| = N² - 1)."""
    w = jnp.asarray([[0.3, 0.16], [-0.4, 0.16], [0.5, 0.16], [1.0, 0.02]], jnp.float32)
    u = jnp.asarray([0.0, 0.02], jnp.float32)
    assert int(winner(w, u, EKMConfig(neurons=2, priority=3))) == 0
    assert int(winner(w, u, EKMConfig(neurons=2, priority=4))) == 3  # everyone competes: Eq. 4.3 alone
    assert int(winner(w, u, EKMConfig(neurons=2, priority=2))) == 0
