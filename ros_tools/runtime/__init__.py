"""How every process of the suite runs its nodes: one executor, one shape, lockstep with the simulator.

* :mod:`.executor`: which rclpy executor spins a process (the C++ EventsExecutor by default,
  ``SingleThreadedExecutor`` as the fallback), chosen in one place;
* :mod:`.lockstep`: the participant side of lockstep simulation (report the sim time this process
  has fully processed, so the simulator never runs ahead of it);
* :mod:`.runner`: the one ``main()`` shape: init, build, share the clock, spin, signals, teardown.
"""
