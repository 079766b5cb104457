"""What every server shares: the node runner, parameter binding, QoS profiles, TF frames,
message conversions, goal runs stepped by timers, the plugin selection topics and the paused-clock watch.
"""
