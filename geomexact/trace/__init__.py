"""Steps, traces and replay: the record of a run, independent of the mesh's dimension.

Layer 2 of ``docs/design.md``: imports only :mod:`geomexact.kernel` and
:mod:`geomexact.errors`.
"""
