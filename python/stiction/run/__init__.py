"""Running a model: ``CompiledModel`` (compiled once, many variants), ``Simulation`` (a
resumable run) and ``simulate`` (what ``Model.simulate`` hands off to).
"""
