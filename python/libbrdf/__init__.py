"""libbrdf: MBK, Beckmann-Kirchhoff and microfacet BRDFs (Butler, Nauyoks & Marciniak 2015) on numpy
arrays.

The compiled module is libbrdf._core (python/libbrdf_module.cpp); everything it defines is
re-exported here, so `import libbrdf; libbrdf.Model(...)` is the whole API. Submodules:
  libbrdf.mitsuba  Mitsuba 3 BSDF plugins for the models (needs the `mitsuba` package; docs/mitsuba.md)
"""
from . import _core
from ._core import *  # noqa: F401,F403 - the public API is the compiled module's

__doc__ = _core.__doc__
__version__ = _core.__version__
__all__ = [name for name in dir(_core) if not name.startswith("_")]

# The types report the package as their home (libbrdf.Model, not libbrdf._core.Model), as before.
for _name in __all__:
    _value = getattr(_core, _name)
    if isinstance(_value, type):
        try:
            _value.__module__ = __name__
        except (AttributeError, TypeError):  # a type that does not allow it keeps libbrdf._core
            pass
del _name, _value
