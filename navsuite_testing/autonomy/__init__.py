"""The seed autonomy's rigs: a scripted navigator (fakes) and the whole stack run as processes (system)."""
