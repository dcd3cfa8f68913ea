"""Reading a URDF file: the project's one URDF reader (strict XML, mesh paths, origins, the description hash).

:class:`geometry.Robot` builds its kinematics from what :func:`read_urdf` returns, and :mod:`sim.model` rewrites
the same parsed tree for pybullet, so both see the same file, the same mesh files and the same rotations.

The XML is parsed strictly (lxml, ``recover=False``): a truncated or otherwise malformed file is refused with
the line and column where it breaks, never half-read. No DTD is loaded, no entity expanded, no network used; a
``<!DOCTYPE>`` is refused outright (a URDF needs none).
"""

from __future__ import annotations

import hashlib
import io
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from lxml import etree
from numpy.typing import NDArray

from .errors import RobotDescriptionError
from .frames import rpy_matrix

_PARSER_OPTIONS = dict(
    recover=False,
    resolve_entities=False,
    no_network=True,
    load_dtd=False,
    dtd_validation=False,
    huge_tree=False,
    remove_comments=True,
    remove_pis=True,
)


@dataclass(frozen=True)
class MeshRef:
    """One ``<mesh>`` element the robot's geometry uses.

    Attributes
    ----------
    link : str
        Link name.
    kind : {"collision", "visual"}
        The element it sits in (visual only for a link without collision elements).
    index : int
        Position among the link's elements of that kind (0-based, document order).
    filename : str
        The filename as written in the URDF.
    path : Path
        The file it resolves to.
    scale : ndarray of shape (3,)
        The element's ``scale`` (ones when absent).
    data : bytes
        The file's contents, read once (hashed and loaded from these bytes).
    """

    link: str
    kind: str
    index: int
    filename: str
    path: Path
    scale: NDArray[np.float64] = field(repr=False)
    data: bytes = field(repr=False)


@dataclass(frozen=True)
class UrdfFile:
    """A URDF file read strictly, with every mesh file its geometry uses.

    Attributes
    ----------
    path : Path
        The URDF file.
    data : bytes
        Its contents.
    root : lxml.etree._Element
        The parsed ``<robot>`` element (comments dropped). Do not mutate it; copy it (``copy.deepcopy``).
    meshes : tuple of MeshRef
        The mesh elements the geometry uses (collision elements, or visual ones for a link without collision
        elements), in document order.
    description_hash : str
        16 hex digits of SHA-256 over the URDF bytes and, per mesh element, its link, kind, index, filename as
        written and the mesh file's bytes: every input to the geometry, mass and joints, and nothing of the
        directory the files sit in.
    """

    path: Path
    data: bytes = field(repr=False)
    root: etree._Element = field(repr=False)
    meshes: tuple[MeshRef, ...] = field(repr=False)
    description_hash: str

    def mesh(self, link: str, kind: str, index: int) -> MeshRef:
        """The :class:`MeshRef` of a link's ``index``-th ``kind`` element (KeyError if it holds no mesh)."""
        for m in self.meshes:
            if (m.link, m.kind, m.index) == (link, kind, index):
                return m
        raise KeyError((link, kind, index))


def parse_xml(data: bytes, name: str) -> etree._ElementTree:
    """Parse URDF bytes strictly; ``name`` labels the messages.

    Raises
    ------
    RobotDescriptionError
        If the XML is not well-formed (with line and column), declares a DTD, or its root is not ``<robot>``.

    Examples
    --------
    >>> parse_xml(b'<robot name="r"><link name="a"/></robot>', "r.urdf").getroot().get("name")
    'r'
    >>> parse_xml(b'<robot name="r"><link name="a">', "r.urdf")
    Traceback (most recent call last):
    ...
    geometry.errors.RobotDescriptionError: 'r.urdf' is not well-formed XML at line 1, column 32: ...
    """
    try:
        tree = etree.parse(io.BytesIO(data), etree.XMLParser(**_PARSER_OPTIONS))
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (exc.lineno, 0)
        msg = re.sub(r",? line \d+, column \d+\s*$", "", (exc.msg or str(exc)).splitlines()[0])
        raise RobotDescriptionError(
            f"'{name}' is not well-formed XML at line {line}, column {col}: {msg}; the file is truncated or "
            "damaged: fix it there or export it again"
        ) from None
    if tree.docinfo.doctype or tree.docinfo.internalDTD is not None:
        raise RobotDescriptionError(
            f"'{name}' declares a DTD ({tree.docinfo.doctype or '<!DOCTYPE>'}); URDF needs none and entities are "
            "not expanded: remove the <!DOCTYPE ...> and write the values out"
        )
    root = tree.getroot()
    if root.tag != "robot":
        raise RobotDescriptionError(
            f"'{name}': the root element is <{root.tag}>, not <robot>; give a URDF file"
        )
    return tree


def resolve_mesh_path(filename: str, urdf_dir: str | Path) -> Path:
    """The file a URDF ``<mesh filename>`` refers to (the one mesh-path rule of the project).

    A relative name is relative to the URDF's directory (never the working directory); ``file://`` is stripped;
    ``package://PKG/REST`` is looked up as ``REST`` next to the URDF, then as ``PKG/REST`` in the URDF's
    directory and each of its parents. The path returned may not exist (the first candidate, for messages).

    Examples
    --------
    >>> resolve_mesh_path("meshes/m.obj", "/robots/r").as_posix()
    '/robots/r/meshes/m.obj'
    >>> resolve_mesh_path("package://r/m.obj", "/robots/r").as_posix()
    '/robots/r/m.obj'
    """
    urdf_dir = Path(urdf_dir)
    if filename.startswith("package://"):
        pkg, _, rest = filename.removeprefix("package://").partition("/")
        candidates = [urdf_dir / rest] + [d / pkg / rest for d in (urdf_dir, *urdf_dir.parents)]
    else:
        candidates = [urdf_dir / filename.removeprefix("file://")]
    return next((c for c in candidates if c.is_file()), candidates[0])


def _floats(text: str | None, n: int, what: str, default: float) -> NDArray[np.float64]:
    if text is None or not text.strip():
        return np.full(n, default)
    try:
        vals = np.array([float(x) for x in text.split()])
    except ValueError:
        raise RobotDescriptionError(f"{what} = {text!r} is not {n} numbers; write {n} numbers") from None
    if len(vals) == 1 and n == 3 and what.endswith("scale"):
        vals = np.repeat(vals, 3)
    if len(vals) != n:
        raise RobotDescriptionError(f"{what} = {text!r} is not {n} numbers; write {n} numbers")
    return vals


def origin_matrix(el: etree._Element | None, what: str = "origin") -> NDArray[np.float64]:
    """4x4 transform of an element's ``<origin xyz rpy>`` child (identity when absent), via :func:`rpy_matrix`.

    Raises
    ------
    RobotDescriptionError
        If ``xyz`` or ``rpy`` is not three numbers.

    Examples
    --------
    >>> t = origin_matrix(etree.fromstring('<joint><origin xyz="1 2 3" rpy="0 0 1.5707963267948966"/></joint>'))
    >>> t[:3, 3].tolist(), (t[:3, :3] @ [1.0, 0.0, 0.0]).round(12).tolist()
    ([1.0, 2.0, 3.0], [0.0, 1.0, 0.0])
    """
    t = np.eye(4)
    o = None if el is None else el.find("origin")
    if o is not None:
        t[:3, 3] = _floats(o.get("xyz"), 3, f"{what} xyz", 0.0)
        t[:3, :3] = rpy_matrix(_floats(o.get("rpy"), 3, f"{what} rpy", 0.0))
    return t


def _mesh_refs(root: etree._Element, urdf_dir: Path) -> list[MeshRef]:
    refs: list[MeshRef] = []
    cache: dict[Path, bytes] = {}
    for link in root.findall("link"):
        name = link.get("name", "")
        kind = "collision" if link.find("collision") is not None else "visual"
        for i, el in enumerate(link.findall(kind)):
            mesh = el.find("geometry/mesh")
            if mesh is None:
                continue
            fname = mesh.get("filename", "")
            if not fname:
                raise RobotDescriptionError(f"link '{name}': a <mesh> has no filename; add filename=\"FILE\"")
            path = resolve_mesh_path(fname, urdf_dir)
            if not path.is_file():
                raise RobotDescriptionError(
                    f"link '{name}': mesh file '{fname}' not found (looked for {path}); "
                    "put it next to the URDF or fix the filename"
                )
            scale = _floats(mesh.get("scale"), 3, f"link '{name}': mesh '{fname}' scale", 1.0)
            if not (np.isfinite(scale).all() and (scale != 0).all()):
                raise RobotDescriptionError(
                    f"link '{name}': mesh '{fname}' scale {scale.tolist()} must be finite and non-zero; fix it"
                )
            key = path.resolve()
            if key not in cache:
                cache[key] = path.read_bytes()
            refs.append(MeshRef(name, kind, i, fname, path, scale, cache[key]))
    return refs


_SHAPE_NUMBERS = {
    "box": (("size", 3),),
    "cylinder": (("radius", 1), ("length", 1)),
    "sphere": (("radius", 1),),
}
"""The numbers of each primitive shape (attribute, count), each finite and positive."""


def _check_geometry_numbers(root: etree._Element) -> None:
    """Every geometry element of every link, visual and collision alike (rendering and the trial video read
    visual meshes, the landscape only some of them): a mesh ``scale`` finite and non-zero, a primitive's size
    finite and positive."""
    for link in root.findall("link"):
        name = link.get("name", "")
        for el in (*link.findall("collision"), *link.findall("visual")):
            geometry = el.find("geometry")
            if geometry is None:
                continue
            what = f"link '{name}': {el.tag}"
            mesh = geometry.find("mesh")
            if mesh is not None:
                fname = mesh.get("filename", "")
                if not fname:
                    raise RobotDescriptionError(f'{what}: a <mesh> has no filename; add filename="FILE"')
                scale = _floats(mesh.get("scale"), 3, f"{what} mesh '{fname}' scale", 1.0)
                if not (np.isfinite(scale).all() and (scale != 0).all()):
                    raise RobotDescriptionError(
                        f"{what} mesh '{fname}' scale {scale.tolist()} must be finite and non-zero; fix it"
                    )
            for shape, attributes in _SHAPE_NUMBERS.items():
                prim = geometry.find(shape)
                if prim is None:
                    continue
                for attr, n in attributes:
                    vals = _floats(prim.get(attr), n, f"{what} {shape} {attr}", np.nan)
                    if not (np.isfinite(vals).all() and (vals > 0).all()):
                        raise RobotDescriptionError(
                            f"{what} {shape} {attr} = {prim.get(attr)!r} must be {n} finite positive "
                            f"number{'s' if n > 1 else ''}; fix it"
                        )


def read_urdf(path: str | Path) -> UrdfFile:
    """Read a URDF file strictly, with the mesh files its geometry uses, and hash them.

    Parameters
    ----------
    path : path
        URDF file.

    Returns
    -------
    UrdfFile

    Raises
    ------
    RobotDescriptionError
        If the file or a mesh file is missing, the XML is malformed (line and column given) or declares a DTD,
        or a mesh ``scale`` or a primitive's size is not finite, in any visual or collision element.
    """
    path = Path(path)
    if not path.is_file():
        raise RobotDescriptionError(f"robot file '{path}' not found; give the path to a .urdf file")
    data = path.read_bytes()
    root = parse_xml(data, str(path)).getroot()
    _check_geometry_numbers(root)
    refs = _mesh_refs(root, path.parent)
    h = hashlib.sha256(b"urdf\0" + data)
    for m in refs:
        h.update(
            f"\0{m.link}\0{m.kind}\0{m.index}\0{m.filename}\0".encode() + hashlib.sha256(m.data).digest()
        )
    return UrdfFile(path, data, root, tuple(refs), h.hexdigest()[:16])
