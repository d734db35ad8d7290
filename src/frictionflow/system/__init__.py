"""Linear structures with friction contacts: the model file, the :class:`System` object and its assembly.

::

    from frictionflow.system import System, load_system, assemble
    system = load_system("two_mass_chain.toml")
    system.with_entry("contact.0.belt", 0.2)
    arrays = assemble(system)          # frictionflow.core.assembly.Assembly

The file format is described in :doc:`/guide/models`.
"""

from .assemble import assemble
from .elements import Contact, Damper, Force, Initial, Normal, Spring
from .model import System, load_system

__all__ = ["Contact", "Damper", "Force", "Initial", "Normal", "Spring", "System", "assemble", "load_system"]
