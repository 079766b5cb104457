"""The orthogonal of sm_atomic_24hr (upstream's ``orthogonals/or_timer.hpp``)."""
