"""nav-bringup: the parameter files and their checks, the plugin catalog, the plan of
servers and managers, the processes or components that run them, fleets and world defaults.
"""
