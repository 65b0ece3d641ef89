"""What a model is: ``Model``, the component descriptions and their catalogue, top-level
parameters and the TOML model file, and what a run is set up with (``runinfo``).

It never runs anything itself: ``Model.simulate`` and the other convenience methods hand off
to ``stiction.run`` (and ``modelica``/``fmu``) through a one-line import.
"""
