"""An independent check of cases given by their equations or by a bracket, in plain sympy.

Reads case files with tomllib and its own small reader of expressions (Python's ``ast``,
a whitelist of nodes: nothing is evaluated), without the registry package, and decides
every claim by the textbook computation:

* integral: dF/dt = grad F . X, reduced modulo the claim's ``on`` equations;
* casimir: Pi grad F = 0 (bracket form only);
* measure: div(rho X) / rho = div X + X(ln rho), reduced modulo ``on``;
* relation: dF/dt reduced modulo F = 0 and ``on``.

Reduction is by a Groebner basis over Q(parameters) of the equations' numerators, with
sin(v), cos(v) of a state variable as symbols S, C and S**2 + C**2 - 1 in the ideal.
Prints one JSON line per claim: {"case", "claim", "kind", "holds"}; ``holds`` is null
where the reduction could not decide. Used by tests/test_independent_check.py to
cross-check the audit's verdicts on the catalog's cases in these forms.

    python scripts/check_any_form.py data/cases/nonholonomic/*.toml
"""

from __future__ import annotations

import ast
import json
import sys
import tomllib

import sympy as sp

ASSUMPTIONS = {
    "real": {"real": True},
    "positive": {"positive": True},
    "nonzero": {"real": True, "nonzero": True},
    "integer": {"integer": True},
}
FUNCTIONS = {
    "sqrt": sp.sqrt,
    "exp": sp.exp,
    "log": sp.log,
    "sin": sp.sin,
    "cos": sp.cos,
    "tan": sp.tan,
    "asin": sp.asin,
    "acos": sp.acos,
    "atan": sp.atan,
    "sinh": sp.sinh,
    "cosh": sp.cosh,
    "tanh": sp.tanh,
}
OPERATORS = {
    ast.Add: lambda a, b: a + b,
    ast.Sub: lambda a, b: a - b,
    ast.Mult: lambda a, b: a * b,
    ast.Div: lambda a, b: a / b,
    ast.Pow: lambda a, b: a**b,
}


def read(text: str, names: dict) -> sp.Expr:
    """An expression of the case language as sympy, by walking its syntax tree."""

    def walk(node):
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
            return OPERATORS[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            value = walk(node.operand)
            return -value if isinstance(node.op, ast.USub) else value
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return sp.Rational(str(node.value))
        if isinstance(node, ast.Name) and node.id in names:
            return names[node.id]
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in FUNCTIONS
            and not node.keywords
        ):
            return FUNCTIONS[node.func.id](*(walk(a) for a in node.args))
        raise ValueError(f"not an expression of the case language: {ast.dump(node)}")

    return walk(ast.parse(text.strip().replace("^", "**"), mode="eval"))


class System:
    """One case file's state, field, bracket and names."""

    def __init__(self, data: dict):
        self.id = data["id"]
        params = data.get("parameters", {})
        self.params = {n: sp.Symbol(n, **ASSUMPTIONS[k]) for n, k in params.items()}
        system = data["system"]
        self.state = [sp.Symbol(n, real=True) for n in system["variables"]]
        self.names = {"pi": sp.pi, "E": sp.E, **self.params}
        self.names.update({str(x): x for x in self.state})
        for name, text in system.get("definitions", {}).items():
            self.names[name] = read(text, self.names)
        self.pi = None
        if "equations" in system:
            self.field = [read(system["equations"][str(x)], self.names) for x in self.state]
        else:
            n = len(self.state)
            index = {str(x): i for i, x in enumerate(self.state)}
            pi = sp.zeros(n, n)
            for pair, text in system["bracket"].items():
                a, b = (index[p.strip()] for p in pair.split(","))
                pi[a, b] = read(text, self.names)
                pi[b, a] = -pi[a, b]
            self.pi = pi
            h = read(system["hamiltonian"], self.names)
            grad = sp.Matrix([sp.diff(h, x) for x in self.state])
            self.field = list(pi * grad)
        self.trig = {}
        for f in self.field:
            for node in sp.preorder_traversal(f):
                if isinstance(node, (sp.sin, sp.cos)) and node.args[0] in self.state:
                    v = node.args[0]
                    self.trig.setdefault(
                        v, (sp.Symbol(f"S_{v}", real=True), sp.Symbol(f"C_{v}", real=True))
                    )

    def rate(self, f: sp.Expr) -> sp.Expr:
        return sum(sp.diff(f, x) * v for x, v in zip(self.state, self.field, strict=True))

    def divergence(self) -> sp.Expr:
        return sum(sp.diff(v, x) for x, v in zip(self.state, self.field, strict=True))

    def untrig(self, e: sp.Expr) -> sp.Expr:
        e = sp.expand_trig(e)
        for v, (s, c) in self.trig.items():
            e = e.subs({sp.tan(v): s / c}).subs({sp.sin(v): s, sp.cos(v): c})
        return e

    def vanishes(self, expr: sp.Expr, on: list[sp.Expr]) -> bool | None:
        """Whether ``expr`` vanishes where ``on`` vanish (None: not decided)."""
        numerator = sp.expand(sp.numer(sp.together(self.untrig(expr))))
        if numerator == 0:
            return True
        ideal = [s**2 + c**2 - 1 for s, c in self.trig.values()]
        ideal += [sp.expand(sp.numer(sp.together(self.untrig(e)))) for e in on]
        gens = [*self.state, *(s for pair in self.trig.values() for s in pair)]
        if any(not sp.sympify(e).is_polynomial(*gens) for e in [numerator, *ideal]):
            return None  # radicals or other functions of the state: not this script's class
        if not ideal:
            return False
        domain = sp.QQ.frac_field(*self.params.values()) if self.params else sp.QQ
        basis = sp.groebner(ideal, *gens, order="grevlex", domain=domain)
        return basis.reduce(numerator)[1] == 0


def equation(text: str, names: dict) -> sp.Expr:
    left, right = text.split("=")
    return read(left, names) - read(right, names)


def check(data: dict):
    s = System(data)
    for claim in data.get("claims", []):
        f = read(claim["expression"], s.names)
        on = [equation(t, s.names) for t in claim.get("on", [])]
        kind = claim["kind"]
        if kind == "integral":
            holds = s.vanishes(s.rate(f), on)
        elif kind == "casimir":
            grad = sp.Matrix([sp.diff(f, x) for x in s.state])
            results = [s.vanishes(r, on) for r in (s.pi * grad)] if s.pi is not None else [None]
            holds = None if None in results else all(results)
        elif kind == "measure":
            holds = s.vanishes(sp.cancel(s.divergence() + s.rate(sp.log(f))), on)
        elif kind == "relation":
            holds = s.vanishes(s.rate(f), [f, *on])
        else:
            holds = None
        yield {"case": s.id, "claim": claim["label"], "kind": kind, "holds": holds}


def main(paths: list[str]) -> int:
    for path in paths:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
        for line in check(data):
            print(json.dumps(line), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
