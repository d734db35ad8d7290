"""A linear structure with friction contacts: :class:`System`, validated entry by entry, and its model file.

The equation of motion over the generalised coordinates q (names ``dof``) is

    M q'' + C q' + K q = sum_j e_j F_j + sum_i g_i A_i cos(Omega_i t + phi_i)

with K = sum k_s e_s e_s^T over the springs, C = sum c_d e_d e_d^T over the
dampers, contact j rubbing along e_j on a belt at b_j (V_r,j = b_j - e_j^T q')
with F_j = N_j(q) law_j(V_r,j) while slipping, N_j = P_j + n_j^T q (1 without
a normal load), and harmonic forces along g_i.  See :doc:`/guide/models`.
"""

from __future__ import annotations

import tomllib
from contextlib import contextmanager
from dataclasses import InitVar, dataclass, field
from pathlib import Path
from typing import Any, Iterator, Mapping

import numpy as np

from ..friction import FrictionLaw
from ..friction.registry import SWITCH_LAW, law_class
from ..params import BeltOscillator
from . import checks, entries, parse
from .elements import Contact, Damper, Force, Initial, Normal, Spring, vector


@contextmanager
def labelled(label: str) -> Iterator[None]:
    """Put ``label`` (``model m.toml``) in front of the one-line message of a ValueError or TypeError raised inside."""
    try:
        yield
    except (ValueError, TypeError) as e:
        raise type(e)(f"{label}: {e}") from None


@dataclass(frozen=True)
class System:
    """A linear structure with friction contacts (the model a multi-DOF run simulates).

    Every entry is checked on construction; a bad one raises a one-line
    ``ValueError`` (``TypeError`` for an element of the wrong class) naming
    the file (``source``), the element and the entry with its allowed values.

    Parameters
    ----------
    dof:
        Names of the generalised coordinates q, in order (identifiers, none twice).
    mass:
        The mass matrix: its diagonal (n numbers > 0) or the full matrix (n rows of n numbers,
        symmetric positive definite).
    springs, dampers, contacts, forces:
        The elements, in file order (their names are ``spring.0``, ``damper.0``, ...).  Contacts along dependent
        directions are a model, but the switching engines cannot run it (two stuck contacts along dependent
        directions hold indeterminate forces): ``simulate``, ``orbit`` and sweeps refuse it, ``stability`` takes it.
    initial:
        The initial state (missing entries 0), each entry of magnitude at most 1e15 as every number of a model.
    source:
        The file the model was read from, for messages (None: built in Python).
    start:
        Check the initial state as a start, every normal load > 0 there (not kept; False for a study that never
        runs from it, :meth:`with_entries`).
    """

    dof: tuple[str, ...]
    mass: tuple[Any, ...]
    springs: tuple[Spring, ...] = ()
    dampers: tuple[Damper, ...] = ()
    contacts: tuple[Contact, ...] = ()
    forces: tuple[Force, ...] = ()
    initial: Initial = field(default_factory=Initial)
    source: str | None = field(default=None, compare=False, repr=False)
    # (not kept) whether the initial state must be a start (every normal load > 0 there); False for a study that
    # never runs from it (the stability of steady sliding)
    start: InitVar[bool] = True

    def __post_init__(self, start: bool = True) -> None:
        with labelled(self.label):
            for name, value in self._validated(start).items():
                object.__setattr__(self, name, value)

    @property
    def label(self) -> str:
        """Names the model in messages (``model FILE``, or ``model`` when it was built in Python)."""
        return "model" if self.source is None else f"model {self.source}"

    def _validated(self, start: bool) -> dict[str, Any]:
        """Every field checked and converted (floats, (dof, value) pairs in dof order)."""
        dof = checks.dof_names(self.dof)
        out: dict[str, Any] = {"dof": dof, "mass": _mass(self.mass, dof)}
        out["springs"] = tuple(Spring(checks.direction(a, s.on, dof), checks.nonnegative(f"{a}.k", s.k))
                               for a, s in _elements(self.springs, "spring", Spring))
        out["dampers"] = tuple(Damper(checks.direction(a, d.on, dof), checks.nonnegative(f"{a}.c", d.c))
                               for a, d in _elements(self.dampers, "damper", Damper))
        out["contacts"] = tuple(_contact(a, c, dof) for a, c in _elements(self.contacts, "contact", Contact))
        out["forces"] = tuple(Force(checks.direction(a, f.on, dof), checks.nonnegative(f"{a}.amplitude", f.amplitude),
                                    checks.positive(f"{a}.omega", f.omega), checks.number(f"{a}.phi", f.phi))
                              for a, f in _elements(self.forces, "force", Force))
        if not isinstance(self.initial, Initial):
            raise TypeError(f"initial must be an Initial, got {self.initial!r}")
        given = {key: checks.coefficients("initial", pairs, dof, key, limit=None)  # checks.initial's range below
                 for key, pairs in (("q", self.initial.q), ("v", self.initial.v))}
        out["initial"] = Initial(*(_full(checks.initial("initial", key, pairs), dof) for key, pairs in given.items()))
        q0 = vector(out["initial"].q, dof)
        for j, contact in enumerate(out["contacts"]):
            if start:
                _loaded(f"contact.{j}", contact.normal, q0, dof)
        return out

    # -- construction --------------------------------------------------------
    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, source: str | None = None, start: bool = True) -> "System":
        """The system a mapping describes (the tables of a model file; see :doc:`/guide/models`).

        Parameters
        ----------
        data:
            ``dof``, ``mass``, the arrays of tables ``spring``, ``damper``, ``contact``, ``force`` and the
            table ``initial``; a contact's ``friction`` is a registered law's name (or a law object) with
            the law's own parameters beside it.
        source:
            The file it was read from, for messages.
        start:
            Check the initial state as a start (every normal load > 0 there); False for a study that
            never runs from it.
        """
        with labelled("model" if source is None else f"model {source}"):
            values = parse.fields(data)
        return cls(**values, source=source, start=start)

    @classmethod
    def single_mass(cls, oscillator: BeltOscillator, friction: FrictionLaw | None = None, *, x0: float = 0.0,
                    v0: float = 0.0) -> "System":
        """The single mass on a belt, X'' + 2 zeta X' + X = F_c + F_ex cos(Omega t + phi), as a system.

        One dof ``x`` of mass 1, a spring k = 1 and a damper c = 2 zeta on it, one contact on it with
        the belt at V_b and ``friction``, and the harmonic force when F_ex != 0.

        Parameters
        ----------
        oscillator:
            zeta, V_b and the external force.
        friction:
            The contact's law (default: Coulomb's switch law with its default parameters).
        x0, v0:
            The initial state X(0), X'(0).
        """
        law = law_class(SWITCH_LAW)() if friction is None else friction
        forces = (Force({"x": 1.0}, oscillator.fex, oscillator.omega, oscillator.phi),) if oscillator.fex != 0.0 else ()
        return cls(dof=("x",), mass=(1.0,), springs=(Spring({"x": 1.0}, 1.0),),
                   dampers=(Damper({"x": 1.0}, 2.0 * oscillator.zeta),),
                   contacts=(Contact({"x": 1.0}, oscillator.vb, law),), forces=forces,
                   initial=Initial({"x": x0}, {"x": v0}))

    def to_dict(self) -> dict[str, Any]:
        """The model as a mapping in the file's layout; :meth:`from_dict` gives the same system back.

        A contact's law appears as its registry name and every parameter value; a law built from a
        function (not buildable by name) appears as its object.
        """
        out: dict[str, Any] = {"dof": list(self.dof), "mass": [list(r) if isinstance(r, tuple) else r for r in self.mass]}
        kinds = {
            "spring": [{"on": dict(s.on), "k": s.k} for s in self.springs],
            "damper": [{"on": dict(d.on), "c": d.c} for d in self.dampers],
            "contact": [_contact_dict(c) for c in self.contacts],
            "force": [{"on": dict(f.on), "amplitude": f.amplitude, "omega": f.omega, "phi": f.phi} for f in self.forces],
        }
        out.update({kind: items for kind, items in kinds.items() if items})
        out["initial"] = {"q": dict(self.initial.q), "v": dict(self.initial.v)}
        return out

    # -- names and arrays ----------------------------------------------------------
    @property
    def n(self) -> int:
        """The number of dof."""
        return len(self.dof)

    @property
    def spring_names(self) -> tuple[str, ...]:
        """``spring.0``, ``spring.1``, ... in file order."""
        return tuple(f"spring.{i}" for i in range(len(self.springs)))

    @property
    def damper_names(self) -> tuple[str, ...]:
        """``damper.0``, ... in file order."""
        return tuple(f"damper.{i}" for i in range(len(self.dampers)))

    @property
    def contact_names(self) -> tuple[str, ...]:
        """``contact.0``, ... in file order."""
        return tuple(f"contact.{i}" for i in range(len(self.contacts)))

    @property
    def force_names(self) -> tuple[str, ...]:
        """``force.0``, ... in file order."""
        return tuple(f"force.{i}" for i in range(len(self.forces)))

    @property
    def element_names(self) -> tuple[str, ...]:
        """Every element's name (the springs, dampers, contacts and forces), each kind in file order."""
        return self.spring_names + self.damper_names + self.contact_names + self.force_names

    @property
    def mass_matrix(self) -> np.ndarray:
        """M as an (n, n) float64 array."""
        if isinstance(self.mass[0], tuple):
            return np.array(self.mass, dtype=np.float64)
        return np.diag(np.array(self.mass, dtype=np.float64))

    @property
    def q0(self) -> np.ndarray:
        """q(0) over the dof."""
        return vector(self.initial.q, self.dof)

    @property
    def v0(self) -> np.ndarray:
        """q'(0) over the dof."""
        return vector(self.initial.v, self.dof)

    # -- entries -------------------------------------------------------------------
    def entries(self) -> tuple[str, ...]:
        """The address of every numeric entry of the model (``mass.0``, ``spring.1.k``, ``contact.0.fd``, ...).

        Directions list the dof they give (``spring.1.on.x2``); the initial state lists every dof.
        """
        return entries.addresses(self)

    def entry(self, address: str) -> float:
        """The value of the entry at ``address`` (a direction's or the initial state's missing dof: 0).

        Parameters
        ----------
        address:
            ``kind.index.key`` (``contact.0.belt``, ``spring.1.k``, ``spring.1.on.x2``,
            ``contact.0.normal.preload``), ``mass.i`` (a diagonal entry), ``mass.i.j`` or
            ``initial.q.x1`` / ``initial.v.x1``.
        """
        with labelled(self.label):
            return entries.value(self, address)

    def with_entry(self, address: str, value: Any, *, start: bool = True) -> "System":
        """A new system with the entry at ``address`` set to ``value``, validated like a file's.

        Parameters
        ----------
        address:
            As for :meth:`entry`; ``mass.i.j`` sets both M_ij and M_ji.
        value:
            The new value.
        start:
            As for :meth:`from_dict`.
        """
        return self.with_entries({address: value}, start=start)

    def with_entries(self, values: Mapping[str, Any], *, start: bool = True) -> "System":
        """A new system with each entry of ``values`` (address -> value) set, validated together like a file's
        (entries that bound each other, such as a contact's ``fd`` and ``fs``, move at once).

        Parameters
        ----------
        values:
            Addresses as for :meth:`entry`, and their new values.
        start:
            As for :meth:`from_dict`: False where the study never runs from the initial state (a normal
            load the new values leave <= 0 there is then no error).
        """
        with labelled(self.label):
            data = entries.replaced_all(self, values)
        return type(self).from_dict(data, source=self.source, start=start)


def load_system(path: str | Path) -> System:
    """Read a model file (TOML; the format is in :doc:`/guide/models`).

    Parameters
    ----------
    path:
        The file.  A missing, unreadable or malformed file, and every bad entry, raise a one-line
        ``ValueError`` naming it.
    """
    label = f"model {path}"
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except tomllib.TOMLDecodeError as e:
        raise ValueError(f"{label}: not valid TOML ({e})") from None
    except UnicodeDecodeError as e:
        raise ValueError(f"{label}: not UTF-8 text (byte {e.start})") from None
    except OSError as e:
        raise ValueError(f"{label}: cannot read it: {e.strerror or e}") from None
    return System.from_dict(data, source=str(path))


def _elements(items: Any, kind: str, cls: type) -> list[tuple[str, Any]]:
    """(address, element) for each element of one kind; TypeError for an element of another class."""
    if isinstance(items, (str, bytes, Mapping)) or not isinstance(items, (list, tuple)):
        raise TypeError(f"{kind} elements must be a tuple of {cls.__name__}, got {items!r}")
    for i, item in enumerate(items):
        if not isinstance(item, cls):
            raise TypeError(f"{kind}.{i} must be a {cls.__name__}, got {item!r}")
    return [(f"{kind}.{i}", item) for i, item in enumerate(items)]


def _full(pairs: tuple[tuple[str, float], ...], dof: tuple[str, ...]) -> tuple[tuple[str, float], ...]:
    """Every dof's value (missing: 0), so that equal states compare equal however they were written."""
    given = dict(pairs)
    return tuple((name, given.get(name, 0.0)) for name in dof)


def _contact(address: str, c: Contact, dof: tuple[str, ...]) -> Contact:
    if not isinstance(c.law, FrictionLaw):
        raise TypeError(f"{address}.friction must be a friction law object, got {c.law!r}")
    normal = c.normal
    if normal is not None:
        if not isinstance(normal, Normal):
            raise TypeError(f"{address}.normal must be a Normal, got {normal!r}")
        normal = Normal(checks.number(f"{address}.normal.preload", normal.preload),
                        checks.coefficients(address, normal.on, dof, "normal"))
    return Contact(checks.direction(address, c.on, dof), checks.number(f"{address}.belt", c.belt), c.law, normal)


def _loaded(address: str, normal: Normal | None, q0: np.ndarray, dof: tuple[str, ...]) -> None:
    """Refuse a normal load N = preload + n . q that is not > 0 at the initial state."""
    if normal is None:
        return
    load = normal.preload + float(vector(normal.on, dof) @ q0)
    if not load > 0.0:
        raise ValueError(f"{address}.normal: the normal load preload + n.q must be > 0 at the initial state, "
                         f"got {load:g}")


def _contact_dict(c: Contact) -> dict[str, Any]:
    out: dict[str, Any] = {"on": dict(c.on), "belt": c.belt}
    if c.law.configurable:
        out.update({"friction": c.law.name, **c.law.values()})
    else:
        out["friction"] = c.law
    if c.normal is not None:
        out["normal"] = {"preload": c.normal.preload, **dict(c.normal.on)}
    return out


def _mass(value: Any, dof: tuple[str, ...]) -> tuple[Any, ...]:
    """The mass: a diagonal of n numbers > 0, or an n x n symmetric positive-definite matrix."""
    n = len(dof)
    value = value.tolist() if isinstance(value, np.ndarray) else value
    shape = f"{n} numbers > 0 (the diagonal, one per dof: {', '.join(dof)}) or a {n} x {n} matrix"
    if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"mass must be {shape}, got {value!r}")
    if not all(isinstance(row, (list, tuple)) for row in value):
        if len(value) != n:
            raise ValueError(f"mass must be {shape}, got {len(value)} numbers")
        return tuple(checks.positive(f"mass.{i}", x) for i, x in enumerate(value))
    if len(value) != n or any(len(row) != n for row in value):
        raise ValueError(f"mass must be {shape}, got rows of lengths {[len(row) for row in value]}")
    m = tuple(tuple(checks.number(f"mass.{i}.{j}", x) for j, x in enumerate(row)) for i, row in enumerate(value))
    for i in range(n):
        for j in range(i + 1, n):
            if m[i][j] != m[j][i]:
                raise ValueError(f"mass must be symmetric: mass.{i}.{j} = {m[i][j]!r} but mass.{j}.{i} = {m[j][i]!r}")
    try:
        np.linalg.cholesky(np.array(m))
    except np.linalg.LinAlgError:
        low = float(np.linalg.eigvalsh(np.array(m))[0])
        raise ValueError(f"mass must be positive definite, got a matrix whose smallest eigenvalue is {low:g}") from None
    return m
