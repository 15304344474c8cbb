"""Reading and writing: JSON results (robot description files and URDF import come here later)."""

from mobman.io.results import dump_json, to_jsonable

__all__ = ["dump_json", "to_jsonable"]
