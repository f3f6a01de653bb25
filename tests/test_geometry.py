"""Object geometry in the language: units, inheritance, round trips, the command line, meshes."""

import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from oacdsl.compiler import compile_sources, load_library, parse_text, print_module
from oacdsl.geometry import resolve, si
from oacdsl.model import Dim, Geometry, Module, ObjectClass, Point, Quantity, Shape

ROOT = Path(__file__).resolve().parents[1]
STANDARD = sorted((ROOT / "library").glob("*.oac"))


def test_sizes_with_and_without_units_are_the_same_length():
    lib = parse_text("class A { shape box(length 12cm, width 120mm, height 0.12) mass 150g }")
    (shape,) = lib.decls[0].geometry.shapes
    assert {d.name: si(d.value, "length") for d in shape.dims} == pytest.approx(
        {"length": 0.12, "width": 0.12, "height": 0.12}
    )
    assert si(lib.decls[0].geometry.mass, "mass") == pytest.approx(0.15)


def test_instances_override_their_classes_property_by_property():
    text = """
class Pot : Container { shape shell(radius 10cm, height 8cm, wall 5mm) mass 1kg colour red }
class BigPot : Pot { mass 2kg }
scene s {
    pot : BigPot { colour blue }
    odd : BigPot { shape cylinder(radius 3cm, height 5cm) }
}
"""
    result = compile_sources({"lib.oac": text, **{str(p): p.read_text() for p in STANDARD}})
    assert result.ok, [d.header() for d in result.diagnostics]
    from oacdsl.library import Library

    lib = Library(result.modules)
    scene = lib.scenes["s"]
    pot = resolve(lib, scene.instance("pot"))
    assert pot.colour == "blue" and si(pot.mass, "mass") == 2.0 and pot.shapes[0].primitive == "shell"
    assert pot.container and pot.role == "object"
    odd = resolve(lib, scene.instance("odd"))
    assert [s.primitive for s in odd.shapes] == ["cylinder"] and not odd.container
    assert odd.colour == "red" and si(odd.mass, "mass") == 2.0


def test_a_class_without_shapes_has_no_geometry():
    lib = load_library(STANDARD)
    assert resolve(lib, lib.scenes["kitchen"].instance("table")).role == "table"
    from oacdsl.model import Instance

    assert resolve(lib, Instance(name="x", classes=("Graspable",))) is None


_units = st.sampled_from(["", "m", "cm", "mm"])
_q = st.builds(
    Quantity,
    value=st.floats(min_value=-1e6, max_value=1e6, allow_nan=False).map(lambda x: round(x, 4)),
    unit=_units,
)
_point = st.builds(Point, x=_q, y=_q, z=_q)
_shape = st.builds(
    Shape,
    primitive=st.sampled_from(["box", "cylinder", "shell", "mesh", "hand"]),
    dims=st.lists(
        st.builds(Dim, name=st.sampled_from(["radius", "height", "wall"]), value=_q), max_size=3
    ).map(tuple),
    file=st.none() | st.sampled_from(["a.stl", 'we"ird.obj']),
    at=st.none() | _point,
)
_geometry = st.builds(
    Geometry,
    shapes=st.lists(_shape, max_size=3).map(tuple),
    mass=st.none()
    | st.builds(Quantity, value=st.floats(0.001, 100.0), unit=st.sampled_from(["", "g", "kg"])),
    friction=st.none() | st.floats(0.01, 3.0),
    colour=st.none() | st.sampled_from(["red", "steel"]),
    markers=st.lists(_point, max_size=3).map(tuple),
)


@given(_geometry)
def test_printing_and_parsing_geometry_gives_the_same_model(geometry):
    module = Module(path="g.oac", decls=(ObjectClass(name="A", parents=("B",), geometry=geometry),))
    text = print_module(module)
    assert parse_text(text, "g.oac") == module
    assert print_module(parse_text(text)) == text


def test_oacc_compile_reports_a_bad_size_with_its_location(tmp_path):
    bad = tmp_path / "jug.oac"
    bad.write_text("class Jug : Container {\n    shape shell(radius 5cm, height 12cm, wall 5furlong)\n}\n")
    out = subprocess.run(
        [sys.executable, "-m", "oacdsl", "compile", "library", str(bad)],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert out.returncode == 1
    first = out.stderr.splitlines()[0]
    assert first == f"{bad}:2:48: error[E032]: unknown unit 'furlong' in 'wall' of shell (valid: cm, m, mm)"
    assert "Traceback" not in out.stderr


def test_oacc_fmt_prints_geometry_canonically(tmp_path):
    src = tmp_path / "a.oac"
    src.write_text("class A:Graspable{shape box(length 1cm,width 2cm,height 3cm) mass 5g}\n")
    out = subprocess.run(
        [sys.executable, "-m", "oacdsl", "fmt", str(src)], capture_output=True, text=True, cwd=ROOT
    )
    assert out.returncode == 0, out.stderr
    assert src.read_text() == (
        "class A : Graspable {\n    shape box(length 1cm, width 2cm, height 3cm)\n    mass 5g\n}\n"
    )


#: A 10 cm cube with a corner at the origin, in millimetres (Wavefront OBJ).
_CUBE_OBJ = (
    "".join(f"v {x} {y} {z}\n" for x in (0, 100) for y in (0, 100) for z in (0, 100))
    + "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n"
)


def test_a_mesh_beside_the_oac_file_is_checked_and_built(tmp_path):
    pytest.importorskip("mujoco", reason="building objects needs the 'robot' extra (mujoco)")
    from oacdsl.runtime.build import build_model
    from oacdsl.runtime.layout import plan_layout

    (tmp_path / "block.obj").write_text(_CUBE_OBJ)
    lib_file = tmp_path / "block.oac"
    lib_file.write_text(
        "class Block : Graspable {\n"
        '    shape mesh("block.obj", scale 0.001) at (-5cm, -5cm, 0)\n'
        "    mass 300g\n}\n"
        "scene bench {\n    left_hand, right_hand : Hand\n    block : Block\n"
        "    table : Table environment\n}\n"
    )
    standard = {str(p): p.read_text() for p in STANDARD}
    missing = compile_sources(
        {**standard, str(lib_file): lib_file.read_text().replace("block.obj", "nope.obj")}
    )
    assert [d.code for d in missing.diagnostics if d.severity == "error"] == ["E034"]
    lib = load_library([*STANDARD, lib_file])
    layout = plan_layout(lib, lib.scenes["bench"])
    block = layout.bodies["block"]
    # a 10 cm cube centred on the z axis: 7.1 cm to a corner, 10 cm high
    assert block.radius == pytest.approx(0.0707, abs=1e-3) and block.height == pytest.approx(0.1, abs=1e-6)
    model = build_model(layout).model
    assert model.body("block").mass[0] == pytest.approx(0.3)
    assert model.ngeom > 0 and model.nmesh == 1


@pytest.mark.parametrize(
    ("doc", "start"), [("language.md", "### Geometry\n\n```\n"), ("runtime.md", "```\nclass Jug")]
)
def test_the_docs_geometry_examples_compile_with_the_standard_library(doc, start):
    text = (ROOT / "docs" / doc).read_text(encoding="utf-8")
    begin = text.index(start) + len(start) - (len("class Jug") if start.endswith("Jug") else 0)
    block = text[begin : text.index("```", begin)]
    assert "shape" in block
    result = compile_sources({**{str(p): p.read_text() for p in STANDARD}, f"{doc}.oac": block})
    assert result.diagnostics == [], [d.header() for d in result.diagnostics]
