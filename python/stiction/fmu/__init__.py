"""FMI export: a model as an FMI 2 or 3 Co-Simulation FMU (``export``) with its model
description (``description``).
"""

from stiction.fmu.export import export_fmu, runtime_library

__all__ = ["export_fmu", "runtime_library"]
