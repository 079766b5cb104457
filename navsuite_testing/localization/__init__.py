"""The localization rig: map_server + amcl + lifecycle manager (nodes) and sim2d's drifting tour (tour)."""
