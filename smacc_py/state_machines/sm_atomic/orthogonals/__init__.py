"""The orthogonal of sm_atomic (upstream's ``orthogonals/or_timer.hpp``)."""
