"""mobman.model.kinds: the registry of classes by ``kind`` (add, get, kinds, the unknown-kind and taken-kind
errors) and import_package, also as the task and law registries use them."""

from __future__ import annotations

import sys

import pytest

from mobman.errors import ModelError
from mobman.model.kinds import Kinds, import_package


class _Base:
    kind = ""


class _Reach(_Base):
    kind = "reach"


class _Grasp(_Base):
    kind = "grasp"


class _Unnamed(_Reach):
    """Inherits ``kind`` without setting it: not registered."""


@pytest.fixture
def registry() -> Kinds:
    kinds: Kinds = Kinds("widget")
    for cls in (_Reach, _Grasp, _Unnamed, _Base):
        kinds.add(cls)
    return kinds


def test_classes_are_found_by_their_kind(registry):
    assert registry.get("reach") is _Reach
    assert registry.get("grasp") is _Grasp
    assert registry.kinds() == ("grasp", "reach")
    assert registry.what == "widget"


def test_classes_without_their_own_kind_are_not_registered(registry):
    """A subclass inheriting its parent's kind, and a class with an empty kind, leave the registry as is."""
    assert registry.get("reach") is _Reach
    assert "" not in registry.kinds()
    with pytest.raises(ModelError, match="widget kind '' unknown"):
        registry.get("")


def test_unknown_kind_names_the_family_suggests_the_closest_and_lists_the_known(registry):
    with pytest.raises(ModelError) as info:
        registry.get("reech")
    message = str(info.value)
    assert message == "widget kind 'reech' unknown; did you mean 'reach'? known: grasp, reach"


def test_unknown_kind_without_a_close_name_lists_the_known(registry):
    with pytest.raises(ModelError) as info:
        registry.get("zzzzzzzz")
    assert str(info.value) == "widget kind 'zzzzzzzz' unknown; known: grasp, reach"


@pytest.mark.parametrize("kind", [None, 3, ("reach",)])
def test_a_kind_that_is_not_a_string_is_a_model_error(registry, kind):
    with pytest.raises(ModelError, match="widget kind .* unknown; known: grasp, reach"):
        registry.get(kind)


def test_an_empty_registry_says_so():
    with pytest.raises(ModelError, match="law kind 'x' unknown; known: $"):
        Kinds("law").get("x")


def test_a_kind_taken_by_another_class_is_refused(registry):
    other = type("Reach", (_Base,), {"kind": "reach", "__module__": "elsewhere"})
    with pytest.raises(ModelError) as info:
        registry.add(other)
    assert "widget kind 'reach' is already" in str(info.value)
    assert f"{_Reach.__module__}._Reach" in str(info.value)
    assert registry.get("reach") is _Reach


def test_the_same_class_defined_again_replaces_itself(registry):
    """A module imported again (same module and qualified name) registers its new class object."""
    again = type("_Reach", (_Base,), {"kind": "reach", "__module__": _Reach.__module__})
    registry.add(again)
    assert registry.get("reach") is again
    assert registry.kinds() == ("grasp", "reach")


def test_import_package_imports_every_module_of_a_package(tmp_path, monkeypatch):
    package = tmp_path / "kindpkg_for_test"
    package.mkdir()
    (package / "__init__.py").write_text("")
    (package / "alpha.py").write_text("LOADED = True\n")
    (package / "beta.py").write_text("LOADED = True\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    import kindpkg_for_test

    try:
        import_package("kindpkg_for_test", kindpkg_for_test.__path__)
        assert sys.modules["kindpkg_for_test.alpha"].LOADED
        assert sys.modules["kindpkg_for_test.beta"].LOADED
    finally:
        for name in ("kindpkg_for_test", "kindpkg_for_test.alpha", "kindpkg_for_test.beta"):
            sys.modules.pop(name, None)


def test_the_task_registry_holds_every_task_module():
    from mobman.model.tasks import Elevation, MountPosition, Position, Stack, task_class, task_kinds
    from mobman.model.tasks.base import TASKS

    assert {"position", "mount_position", "elevation", "stack", "pose", "planar_angle"} <= set(task_kinds())
    assert task_kinds() == TASKS.kinds()
    for cls in (Position, MountPosition, Elevation, Stack):
        assert task_class(cls.kind) is cls
    with pytest.raises(ModelError, match="task kind 'positon' unknown; did you mean 'position'\\?"):
        task_class("positon")


def test_the_law_registry_names_its_family():
    from mobman.control.laws.base import LAWS

    assert LAWS.what == "law" and LAWS.kinds()
    with pytest.raises(ModelError, match="^law kind 'no-such-law' unknown; .*known: "):
        LAWS.get("no-such-law")
