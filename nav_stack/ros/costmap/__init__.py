"""Costmap2DROS: the layered costmap node, its parameters and its publishers.
"""
