"""Lifecycle: the managed node base every server derives from (``node``) and the
lifecycle manager with its bonds.
"""
