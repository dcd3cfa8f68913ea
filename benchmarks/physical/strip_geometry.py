"""A copy of a URDF in which some links keep their mass but lose their shape (issue #15: which part's contact
matters?).

Each named link's ``<visual>`` and ``<collision>`` elements are dropped; its ``<inertial>`` stays, so the robot
weighs and swings as before but that part can no longer touch the ground, in the landscape (its hull points are
gone) and in the simulation (no collision shape). Mesh paths are made absolute, so the copy loads from anywhere.
Feed the copy to any command that takes ``--robot``, e.g. without the leg's rod and sphere:

    PYTHONPATH=. .venv/bin/python benchmarks/physical/strip_geometry.py ../shared/ref/lab_robot/lab_robot.urdf \
        --link pendulum --out noleg
    landscape physical validate --data ../shared/ref/physical_robot --robot noleg/lab_robot.urdf \
        --model physical-head --phase protocol --cells 75:45,90:15,90:30,90:45 --trials 5 --out validation-noleg

Run:  PYTHONPATH=. .venv/bin/python benchmarks/physical/strip_geometry.py URDF --link NAME [--link NAME ...] [--out DIR]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from xml.etree import ElementTree as ET

from defusedxml import ElementTree as SafeET
from defusedxml.common import DefusedXmlException


def strip(urdf: Path, links: list[str]) -> ET.ElementTree:
    """The URDF's tree with the named links' visual and collision elements removed and mesh paths absolute.

    Raises
    ------
    ValueError
        If the file is not a URDF or names none of the links.
    """
    try:
        tree = SafeET.parse(urdf)
    except (ET.ParseError, DefusedXmlException) as exc:
        raise ValueError(f"{urdf} is not readable XML ({exc}); give a URDF file") from None
    root = tree.getroot()
    if root.tag != "robot":
        raise ValueError(f"{urdf}: the root element is <{root.tag}>, not <robot>; give a URDF file")
    by_name = {el.get("name"): el for el in root.iter("link")}
    unknown = [n for n in links if n not in by_name]
    if unknown:
        raise ValueError(
            f"{urdf} has no link {', '.join(repr(n) for n in unknown)}; its links: {', '.join(sorted(by_name))}"
        )
    for name in links:
        link = by_name[name]
        for el in [*link.findall("visual"), *link.findall("collision")]:
            link.remove(el)
    for mesh in root.iter("mesh"):
        f = mesh.get("filename", "")
        if f and "://" not in f and not Path(f).is_absolute():
            mesh.set("filename", str((urdf.parent / f).resolve()))
    return tree


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("urdf", type=Path)
    ap.add_argument("--link", action="append", required=True, help="a link to strip (repeatable)")
    ap.add_argument("--out", type=Path, default=Path("stripped"), help="output directory [default: stripped]")
    a = ap.parse_args(argv)
    if not a.urdf.is_file():
        print(f"error: {a.urdf} does not exist; give a URDF file", file=sys.stderr)
        return 2
    try:
        tree = strip(a.urdf, a.link)
    except ValueError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    a.out.mkdir(parents=True, exist_ok=True)
    dest = a.out / a.urdf.name
    tree.write(dest, encoding="unicode", xml_declaration=False)
    print(f"wrote {dest}: {', '.join(a.link)} keep their mass, lose their shape")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
