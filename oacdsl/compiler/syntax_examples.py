"""Small bad snippets, each labelled with what is expected where it fails.

:mod:`oacdsl.compiler.syntax` parses each snippet once, notes the parser state
where it fails (and the state below it on the stack), and says "expected
<label>" for any error in that state. To improve a message: add a snippet that
fails at the same place, under the label you want. Snippets are listed with and
without repetitions (one or two parameters, atoms, markers) because LALR states
differ between them. ``tests/test_lang_grammar.py`` checks that every snippet
gets its own label (a snippet that parses is followed by ``@``, as the table does).
"""

from __future__ import annotations

__all__ = ["EXAMPLES"]

_DECL = "a declaration ('class', 'scene', 'grasp' or 'oac')"
_SHAPES = "box, cylinder, sphere, capsule, shell, mesh, balls, hand or table"

#: (what is expected, snippets that fail at the same parser state).
EXAMPLES: list[tuple[str, list[str]]] = [
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
    (
        "'turned' and the object's yaw, the next instance, 'layout', a statement such as 'x at (…)'"
        " or 'x in c', or '}'",
        ["scene s { a at (1, 2)", "scene s { a at (1, 2) :"],
    ),
    (
        "an angle such as 90deg (bare numbers are radians)",
        ["scene s { a at (1, 2) turned", "scene s { a at (1, 2) turned }"],
    ),
    (
        "the next instance, 'layout', a statement such as 'x at (…)' or 'x in c', or '}'",
        ["scene s { a at (1, 2) turned 5", "scene s { a at (1, 2) turned 5deg :"],
    ),
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
    ("the OAC's name", ["oac", "oac ("]),
    ("'(' and the OAC's parameters", ["oac f", "oac f {"]),
    ("a parameter 'name: Class' or ')'", ["oac f(", "oac f(h: H,", "oac f(h: H, o: O,", "oac f(h: H = x,"]),
    ("':' and the parameter's class", ["oac f(h", "oac f(h)", "oac f(h: H, o", "oac f(h: H, o: O, p"]),
    ("the parameter's class", ["oac f(h:", "oac f(h: )", "oac f(h: H, o:"]),
    ("',', '= instance' or ')'", ["oac f(h: H", "oac f(h: H h", "oac f(h: H, o: O", "oac f(h: H, o: O o"]),
    ("',' or ')' after the parameter", ["oac f(h: H = x", "oac f(h: H = x y", "oac f(h: H, o: O = x"]),
    ("the default instance", ["oac f(h: H =", "oac f(h: H = )"]),
    (
        "'{' and the OAC's body",
        [
            "oac f()",
            "oac f() pre",
            "oac f(h: H)",
            "oac f(h: H, o: O)",
            "oac f(h: H,)",
            "oac f(h: H = x)",
        ],
    ),
    ("'pre', 'effect', 'execute SKILL' or 'steps { … }'", ["oac f() {", "oac f() { }", "oac f(h: H) {"]),
    (
        "a relation such as 'h <-> o', 'h <-> nothing' or 'not h <-> o'",
        [
            "oac f() { pre",
            "oac f() { effect",
            "oac f() { pre }",
            "oac f() { effect }",
        ],
    ),
    (
        "a relation, 'effect', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { pre a <-> b,",
            "oac f() { pre a <-> b, c <-> d,",
            "oac f() { pre a <-> nothing,",
            "oac f() { pre not a <-> b,",
        ],
    ),
    (
        "a relation, 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { effect a <-> b,",
            "oac f() { effect a <-> b, c <-> d,",
            "oac f() { pre a <-> b effect c <-> d,",
        ],
    ),
    ("an object or 'nothing' after 'not'", ["oac f() { pre not", "oac f() { pre not }"]),
    (
        "'<->' between the two objects",
        [
            "oac f() { pre a",
            "oac f() { pre a b",
            "oac f() { pre not a",
            "oac f() { pre not a b",
            "oac f() { pre nothing",
            "oac f() { pre not nothing",
            "oac f() { pre a <-> b, c",
        ],
    ),
    (
        "an object or 'nothing' after '<->'",
        [
            "oac f() { pre a <->",
            "oac f() { pre a <-> }",
            "oac f() { pre not a <->",
            "oac f() { pre nothing <->",
            "oac f() { pre not nothing <->",
        ],
    ),
    (
        "',', 'effect', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { pre a <-> b",
            "oac f() { pre a <-> b }",
            "oac f() { pre a <-> nothing",
            "oac f() { pre not a <-> b",
            "oac f() { pre not a <-> nothing",
            "oac f() { pre a <-> b, c <-> d",
            "oac f() { pre nothing <-> a",
            "oac f() { pre not nothing <-> a",
        ],
    ),
    (
        "',', 'execute SKILL' or 'steps { … }'",
        [
            "oac f() { effect a <-> b",
            "oac f() { effect a <-> b }",
            "oac f() { effect a <-> nothing",
            "oac f() { effect not a <-> b",
            "oac f() { effect not a <-> nothing",
            "oac f() { effect a <-> b, c <-> d",
            "oac f() { effect nothing <-> a",
            "oac f() { effect not nothing <-> a",
        ],
    ),
    ("the name of a skill", ["oac f() { execute", "oac f() { execute }"]),
    (
        "the skill's arguments '(a, b)', its parameters '{ name value }' or '}' to close the OAC",
        ["oac f() { execute s", "oac f() { execute s pre"],
    ),
    (
        "the skill's parameters '{ name value }' or '}' to close the OAC",
        ["oac f() { execute s()", "oac f() { execute s(a)", "oac f() { execute s(a) pre"],
    ),
    (
        "a skill parameter such as 'tilt 110deg' or '}'",
        ["oac f() { execute s {", "oac f() { execute s { t 1", "oac f() { execute s { )"],
    ),
    (
        "the parameter's value, a number with its unit such as 110deg",
        ["oac f() { execute s { t", "oac f() { execute s { t }"],
    ),
    (
        "'}' to close the OAC",
        [
            "oac f() { execute s { }",
            "oac f() { execute s { t 1 }",
            "oac f() { steps { }",
            "oac f() { steps { g() }",
        ],
    ),
    ("'{' and the steps", ["oac f() { steps", "oac f() { steps }"]),
    ("a step such as 'grasp(h, o)' or '}'", ["oac f() { steps {", "oac f() { steps { g() )"]),
    (
        "the step's skill parameters '{ tilt 110deg }', the next step such as 'place(h, o)' or '}'",
        [
            "oac f() { steps { g(a)",
            "oac f() { steps { g(a) h(b)",
            "oac f() { steps { g(a) )",
        ],
    ),
    (
        "the next step such as 'place(h, o)' or '}'",
        [
            "oac f() { steps { g(a) { }",
            "oac f() { steps { g(a) { t 1 }",
            "oac f() { steps { g(a) { t 1 } )",
            "oac f() { steps { g(a) { t 1 } h(b) { }",
        ],
    ),
    (
        "a skill parameter of the step such as 'tilt 110deg' or '}'",
        ["oac f() { steps { g(a) {", "oac f() { steps { g(a) { )"],
    ),
    (
        "the step parameter's value, a number with its unit such as 110deg",
        ["oac f() { steps { g(a) { t", "oac f() { steps { g(a) { t }"],
    ),
    (
        "'(' and the step's arguments",
        ["oac f() { steps { g", "oac f() { steps { g }", "oac f() { steps { g() h"],
    ),
    (
        "an argument or ')'",
        ["oac f() { steps { g(", "oac f() { steps { g( }", "oac f() { execute s(", "oac f() { execute s( }"],
    ),
    (
        "an argument",
        [
            "oac f() { execute s(a,",
            "oac f() { steps { g(a,",
            "oac f() { steps { g(a, )",
            "oac f() { steps { g(a, b,",
        ],
    ),
    (
        "',' or ')' after the argument",
        [
            "oac f() { execute s(a",
            "oac f() { execute s(a b",
            "oac f() { steps { g(a",
            "oac f() { steps { g(a b",
            "oac f() { steps { g(a, b",
            "oac f() { steps { g(a, b c",
        ],
    ),
]
