"""The machine's own client (upstream's ``clients/cl_subscriber``)."""
