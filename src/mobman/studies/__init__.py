"""Design studies on top of the analysis:

- :mod:`mobman.studies.placement` where to park the platform for a target;
- :mod:`mobman.studies.floor` keep-out regions of the floor and the disc covering the platform, for placement;
- :mod:`mobman.studies.maps` where around its platform an arm's tool reaches, and how well (reachability maps);
- :mod:`mobman.studies.sweep` a robot's parameters varied over a grid, every design scored;
- :mod:`mobman.studies.reaching` the arm's inverse kinematics within its joint limits, which they share;
- :mod:`mobman.studies.store` chunked, resumable studies in Zarr stores, on a Dask cluster when asked;
- :mod:`mobman.studies.options` the options they share, checked once.
"""
