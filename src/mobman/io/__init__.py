"""Reading and writing: JSON results, numbers typed by users (:mod:`.numbers`), files and results folders written
atomically (:mod:`.output`), TOML spec helpers (:mod:`.spec`), robot description files (:mod:`.robot_file`), URDF
files in and out (:mod:`.urdf`, with the ``robots`` extra), the real robots built in (:mod:`.real_robots`,
registered in :data:`mobman.model.robots.ROBOTS` when mobman is imported; their URDF files are read when first
built)."""

from mobman.io.results import dump_json, to_jsonable

__all__ = ["dump_json", "to_jsonable"]
