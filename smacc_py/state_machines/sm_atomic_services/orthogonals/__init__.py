"""The orthogonals of sm_atomic_services (upstream's ``orthogonals/``)."""
