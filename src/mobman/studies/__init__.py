"""Design studies on top of the analysis: :mod:`mobman.studies.placement` (where to park the platform for a
target)."""
