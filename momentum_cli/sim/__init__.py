"""`momentum simulate`: the motion of a declared scene over time, between and across impacts.

spec (what the file asks for) -> model (bodies, coordinates, effects, contacts)
-> dynamics (accelerations with constraint forces) -> integrate (phases, events,
impacts by the impulse solver) -> output (event table, time series, JSON, CSV, plot).
"""
