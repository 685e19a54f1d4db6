"""Software-in-the-loop: the MuJoCo plant and the glue that drives the control core against it."""
