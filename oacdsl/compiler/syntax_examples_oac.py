"""The bad snippets of an OAC (``oac name(parameters) { … }``) for
:data:`oacdsl.compiler.syntax_examples.EXAMPLES`, each labelled with what is expected where it
fails (the module's docstring says how the table is used)."""

from __future__ import annotations

__all__ = ["OAC_EXAMPLES"]

#: (what is expected, snippets that fail at the same parser state), in an OAC.
OAC_EXAMPLES: list[tuple[str, list[str]]] = [
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
