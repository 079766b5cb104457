"""The seed project's battery-aware patrol (Tannous987/nav_tb3_ws tb3_autonomy) on nav_stack.

Modules: ``node`` (autonomy_node, console ``nav-autonomy``), ``seed_nodes`` (the six BT node
types), ``battery`` (counter and /battery_state sources), ``locations`` (the locations file),
``navigator`` (non-blocking NavigateToPose client), ``clearance`` (can the waffle reach a pose).
"""
