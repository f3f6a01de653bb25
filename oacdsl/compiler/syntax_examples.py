"""Small bad snippets, each labelled with what is expected where it fails.

:mod:`oacdsl.compiler.syntax` parses each snippet once, notes the parser state
where it fails (and the state below it on the stack), and says "expected
<label>" for any error in that state. To improve a message: add a snippet that
fails at the same place, under the label you want. Snippets are listed with and
without repetitions (one or two parameters, atoms, markers) because LALR states
differ between them. ``tests/test_lang_grammar.py`` checks that every snippet
gets its own label (a snippet that parses is followed by ``@``, as the table does). The OAC's
snippets are in :mod:`oacdsl.compiler.syntax_examples_oac`.
"""

from __future__ import annotations

from oacdsl.compiler.syntax_examples_oac import OAC_EXAMPLES

__all__ = ["EXAMPLES"]

_DECL = "a declaration ('class', 'scene', 'grasp' or 'oac')"
_SHAPES = "box, cylinder, sphere, capsule, shell, mesh, balls, hand or table"

#: (what is expected, snippets that fail at the same parser state) at the top level and in
#: classes, scenes and grasps.
_DECLARATIONS: list[tuple[str, list[str]]] = [
    ("':' and the parent classes, '{' and the class's geometry, or " + _DECL, ["class A", "class A B"]),
    (
        "',' and more parent classes, '{' and the class's geometry, or " + _DECL,
        ["class A : B", "class A : B C", "class A : B, C"],
    ),
    (
        _DECL,
        [
            "}",
            "Cup",
            "scene s { }",
            "scene s { a : B }",
            "grasp G { type a approach b }",
            "grasp G { type a approach b offset (1, 2, 3) }",
            "oac f() { execute s }",
            "oac f(h: H) { execute s }",
            "oac f() { steps { } }",
            "oac f(h: H) { steps { } }",
            "scene s { } }",
            "grasp G { type a approach b } }",
            "grasp G { type a approach b offset (1, 2, 3) } }",
            "oac f() { execute s } }",
            "oac f(h: H) { execute s } }",
            "oac f() { steps { } } }",
            "scene s { a : B } }",
        ],
    ),
    (
        "a class name",
        [
            "class",
            "class A :",
            "class A : B,",
            "class A : B, C,",
            "scene s { a :",
            "scene s { a : B,",
            "scene s { a : B, C,",
            "scene s { a, b :",
        ],
    ),
    ("a scene name", ["scene", "scene {"]),
    ("'{' after the scene name", ["scene s", "scene s s"]),
    ("an instance name or '}'", ["scene s {"]),
    ("an instance name", ["scene s { a,", "scene s { a, }", "scene s { a, b,"]),
    (
        "':' and the instance's classes, 'at (x, y)' or 'in CONTAINER'"
        " (after 'layout': auto or demonstrated)",
        ["scene s { a", "scene s { a = b", "scene s { layout", "scene s { layout }"],
    ),
    ("':' and the instances' classes", ["scene s { a, b", "scene s { a, b, c"]),
    ("'(' and the position on the table (x, y)", ["scene s { a at", "scene s { a at x"]),
    (
        "a length such as 56cm (bare numbers are metres)",
        ["scene s { a at (", "scene s { a at (1,", "scene s { a at ( )", "scene s { a at (1, )"],
    ),
    ("',' between x and y", ["scene s { a at (1", "scene s { a at (1 2"]),
    ("')' after x and y", ["scene s { a at (1, 2", "scene s { a at (1, 2, 3"]),
    ("the container the liquid starts in", ["scene s { a in", "scene s { a in }"]),
    ("the number of balls", ["scene s { a in b balls", "scene s { a in b balls }"]),
    (
        "'balls N', the next instance or statement, or '}'",
        ["scene s { a in b", "scene s { a in b :"],
    ),
    (
        "',' and more classes, 'markers (…)', 'environment', '{' and the instance's geometry,"
        " the next instance or '}'",
        [
            "scene s { a : B",
            "scene s { a : B, C",
            "scene s { a, b : B",
            "scene s { a : B :",
        ],
    ),
    (
        "'environment', '{' and the instance's geometry, the next instance or '}'",
        [
            'scene s { a : B markers ("x")',
            'scene s { a : B markers ("x",)',
            "scene s { a : B markers ()",
        ],
    ),
    (
        "'{' and the instance's geometry, the next instance, 'layout', a statement such as"
        " 'x at (…)' or 'x in c', or '}'",
        [
            "scene s { a : B environment",
            'scene s { a : B markers ("x") environment',
            "scene s { a : B environment :",
            "scene s { a : B ignored",
            'scene s { a : B markers ("x") ignored',
            "scene s { a : B ignored :",
            "scene s { a : B untracked",
            "scene s { a : B untracked :",
            "scene s { a in b balls 3",
            "scene s { a at (1, 2)",
            "scene s { layout x",
            "scene s { a in b balls 3 :",
            "scene s { layout x :",
        ],
    ),
    (
        "a quoted marker name such as \"m1\" or ')'",
        [
            "scene s { a : B markers (",
            'scene s { a : B markers ("x",',
            'scene s { a : B markers ("x", "y",',
        ],
    ),
    ("'(' and the marker names", ["scene s { a : B markers", "scene s { a : B markers }"]),
    (
        "',' or ')' in the marker list",
        [
            'scene s { a : B markers ("x"',
            'scene s { a : B markers ("x", "y"',
            'scene s { a : B markers ("x", "y", "z"',
        ],
    ),
    (
        "a shape (" + _SHAPES + ")",
        ["class A { shape", "class A { shape (", "scene s { a : B { shape", "class A { shape }"],
    ),
    (
        "'shape', 'mass', 'friction', 'colour', 'markers' or '}'",
        [
            "class A {",
            "class A { shape box(length 1)",
            "class A { shape hand",
            "class A { friction 1",
            "class A { colour red",
            "class A { markers (1, 2, 3)",
            "class A { shape box at (1, 2, 3)",
            "scene s { a : B {",
        ],
    ),
    (
        "a unit (m, cm, mm; kg, g), 'shape', 'mass', 'friction', 'colour', 'markers' or '}'",
        ["class A { mass 1", "class A { mass 1 2"],
    ),
    (
        "a number with its unit, such as 4cm or 150g",
        [
            "class A { mass",
            "class A { mass }",
            "class A { shape box(length",
            "class A { shape box(length )",
            "class A { shape box at (",
            "class A { shape box at (1,",
            "class A { shape box at (1, 2,",
            "class A { markers (",
        ],
    ),
    (
        "a size such as 'radius 4cm', a quoted file name or ')'",
        ["class A { shape box(", "class A { shape box(1"],
    ),
    ("a size such as 'radius 4cm' or a quoted file name", ["class A { shape box(length 1,"]),
    ("',' or ')' after a size", ["class A { shape box(length 1cm", "class A { shape box(length 1cm 2"]),
    (
        "a unit (m, cm, mm; kg, g), ',' or ')'",
        ["class A { shape box(length 1", "class A { shape box(length 1 2"],
    ),
    ("a friction coefficient (a number)", ["class A { friction", "class A { friction }"]),
    ("a colour name (red, green, …)", ["class A { colour", "class A { colour }"]),
    (
        "'(' and a point (x, y, z) in the object frame",
        ["class A { markers", "class A { shape box at", "class A { markers (1, 2, 3),"],
    ),
    ("the class to grasp", ["grasp", "grasp {"]),
    ("'{' after the class to grasp", ["grasp G", "grasp G type"]),
    ("'type' and a grasp type (power, precision, pinch, rim, handle)", ["grasp G {", "grasp G { approach"]),
    ("a grasp type (power, precision, pinch, rim, handle)", ["grasp G { type", "grasp G { type }"]),
    ("'approach' and a direction (side, top, front)", ["grasp G { type a", "grasp G { type a }"]),
    (
        "an approach direction (side, top, front)",
        ["grasp G { type a approach", "grasp G { type a approach }"],
    ),
    ("'offset (x, y, z)' or '}'", ["grasp G { type a approach b", "grasp G { type a approach b c"]),
    (
        "'(' and three numbers in metres",
        ["grasp G { type a approach b offset", "grasp G { type a approach b offset 1"],
    ),
    (
        "a number (metres)",
        [
            "grasp G { type a approach b offset (",
            "grasp G { type a approach b offset (1,",
            "grasp G { type a approach b offset (1, 2,",
        ],
    ),
    (
        "',' between the three numbers",
        [
            "grasp G { type a approach b offset (1",
            "grasp G { type a approach b offset (1, 2",
        ],
    ),
    ("')' after the three numbers", ["grasp G { type a approach b offset (1, 2, 3"]),
    ("'}' to close the grasp", ["grasp G { type a approach b offset (1, 2, 3)"]),
]

#: (what is expected, snippets that fail at the same parser state): the declarations', then an OAC's
#: (``syntax_examples_oac``).
EXAMPLES: list[tuple[str, list[str]]] = _DECLARATIONS + OAC_EXAMPLES
