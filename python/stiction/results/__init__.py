"""What a run gives back: ``Result`` with its events, derived variables, the energy audit,
the MSL comparison, plots and mode names; ``results.io`` reads and writes the files.
"""
