"""The contact methods, a registry by name: one module per method, one line per method here.

A method module defines ``METHOD``, a :class:`~lutmpi.contact.methods.base.ContactMethod`: its
name, its properties and its stage of the pose solve. The mesh methods of §4.2
(:class:`~lutmpi.contact.methods.base.MeshMethod`) own a compiled kernel built from the shared
stages of :mod:`lutmpi.contact.kernels` (eq. 2 search, §4.6 split); ``reference`` is the
semi-analytic locus solution. A new method is one module plus one line in :data:`MODULES`.
"""

from __future__ import annotations

import importlib

from lutmpi.contact.methods.base import ContactMethod, MeshContact, MeshMethod

#: the method modules of this package, in registry order (one line per method)
MODULES: tuple[str, ...] = (
    "max_distance",
    "max_normal_distance",
    "load_centre",
    "reference",
)
METHODS: dict[str, ContactMethod] = {
    m.name: m for m in (importlib.import_module(f"{__name__}.{name}").METHOD for name in MODULES)
}
#: every method's name, in registry order
METHOD_NAMES: tuple[str, ...] = tuple(METHODS)
#: the methods that search the meshes (§4.2)
MESH_METHOD_NAMES: tuple[str, ...] = tuple(n for n, m in METHODS.items() if m.uses_mesh)


def get_method(name: str) -> ContactMethod:
    """The contact method registered under ``name``; an unknown name raises ``ValueError``
    listing the valid ones."""
    try:
        return METHODS[name]
    except KeyError:
        raise ValueError(f"unknown contact method {name!r}; valid: {list(METHODS)}") from None


__all__ = ["METHODS", "METHOD_NAMES", "MESH_METHOD_NAMES", "ContactMethod", "MeshContact",
           "MeshMethod", "get_method"]
