"""The parser of the case-file expression language: text to sympy, safely.

``parse_expression`` reads text with ``ast.parse`` and walks the tree against
a whitelist (numbers, names, ``+ - * / **``, calls of known functions),
building the sympy expression itself. Nothing is ever evaluated as Python:
no ``eval``, no ``sympify`` of raw text. Every size limit of ``limits`` is
checked before the work it bounds. ``printer.to_text`` writes an expression
back in the same language. The language is described in docs/case-format.md,
"Expressions".

Examples
--------
>>> parse_expression("0.5*gamma1**2 + 1e-3")
gamma1**2/2 + 1/1000
"""

from __future__ import annotations

import ast
import difflib
import math
import re
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

import sympy as sp

from ..errors import ExpressionError
from ..mathematics.mechanics import STATE, s, total_diff
from . import limits
from .limits import ParseBudget

#: The state variables and ``s``, by name.
VARIABLES: Mapping[str, sp.Symbol] = MappingProxyType({str(v): v for v in (*STATE, s)})
#: Named constants.
CONSTANTS: Mapping[str, sp.Expr] = MappingProxyType({"pi": sp.pi, "E": sp.E})
#: The elementary functions of the language, one argument each.
FUNCTIONS: Mapping[str, Callable[..., sp.Expr]] = MappingProxyType(
    {
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
)
#: Names a case file may not declare, with what each one already is.
RESERVED_NAMES: Mapping[str, str] = MappingProxyType(
    {
        **{name: "a variable" for name in VARIABLES},
        **{name: "a function" for name in FUNCTIONS},
        **{name: "a constant" for name in CONSTANTS},
        "diff": "the derivative",
    }
)

_VARIABLE_LIST = "M1, M2, M3, gamma1, gamma2, gamma3 or s"
_UNDEFINED = (sp.zoo, sp.oo, -sp.oo, sp.nan)


@dataclass(frozen=True)
class Namespace:
    """The names a case declares: parameter symbols, arbitrary functions, and for a
    system on its own phase space its state variables and definitions.

    ``functions`` maps a name to its sympy function class and its argument
    symbols (taken from ``registry.mathematics.mechanics``), e.g. ``a -> (a, (s,))``.
    ``variables`` are the case's own state variables by name (None: the reference
    paper's M1..M3, gamma1..gamma3 and s); ``definitions`` map a name to the expression
    it stands for (expanded already) and the parts it counts for in the case's budget
    each time it is used (so that definitions built on definitions cannot grow without
    bound).
    """

    parameters: Mapping[str, sp.Symbol] = field(default_factory=dict)
    functions: Mapping[str, tuple[sp.FunctionClass, tuple[sp.Symbol, ...]]] = field(
        default_factory=dict
    )
    variables: Mapping[str, sp.Symbol] | None = None
    definitions: Mapping[str, tuple[sp.Expr, int]] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "parameters", MappingProxyType(dict(self.parameters)))
        object.__setattr__(self, "functions", MappingProxyType(dict(self.functions)))
        if self.variables is not None:
            object.__setattr__(self, "variables", MappingProxyType(dict(self.variables)))
        object.__setattr__(self, "definitions", MappingProxyType(dict(self.definitions)))

    @property
    def state(self) -> Mapping[str, sp.Symbol]:
        """The state variables by name (the paper's, with ``s``, unless the case names its
        own)."""
        return VARIABLES if self.variables is None else self.variables

    @property
    def paper_state(self) -> bool:
        """Whether the state is the reference paper's (M, gamma, with s = M.gamma)."""
        return self.variables is None

    def variable_list(self) -> str:
        """The state variables as a message lists them."""
        if self.variables is None:
            return _VARIABLE_LIST
        names = list(self.variables)
        return ", ".join(names[:-1]) + f" or {names[-1]}" if len(names) > 1 else names[0]


EMPTY = Namespace()


# --------------------------------------------------------------------------- parsing


def parse_expression(
    text: str, ns: Namespace = EMPTY, budget: ParseBudget | None = None
) -> sp.Expr:
    """The sympy expression that ``text`` denotes in the case-file language.

    Raises ``ExpressionError`` (message, text) for anything outside the language.
    ``budget``, shared by the expressions of one case file, bounds them together.
    """
    if not isinstance(text, str):
        raise TypeError(f"an expression must be a str, not {type(text).__name__}")
    budget = ParseBudget() if budget is None else budget
    if budget.exhausted is not None:
        raise ExpressionError(budget.exhausted, text)
    flat = _check_text(text)
    budget.spend("parts", _count_parts(flat), text)
    tree = _parse_tree(flat, text)
    _check_node_count(tree, text)
    expr, _ = _Builder(flat, text, ns, budget).build(tree.body, 0)
    return expr


def parse_equation(
    text: str, ns: Namespace = EMPTY, budget: ParseBudget | None = None
) -> tuple[sp.Expr, sp.Expr]:
    """(lhs, rhs) of a level-set equation ``lhs = rhs``.

    Errors carry the whole equation as their text.
    """
    if not isinstance(text, str):
        raise TypeError(f"an equation must be a str, not {type(text).__name__}")
    parts = text.split("=")
    if len(parts) != 2 or parts[0][-1:] in ("<", ">", "!") or not all(p.strip() for p in parts):
        raise ExpressionError("an equation needs the form lhs = rhs", text)
    budget = ParseBudget() if budget is None else budget
    try:
        return parse_expression(parts[0], ns, budget), parse_expression(parts[1], ns, budget)
    except ExpressionError as err:
        raise ExpressionError(err.message, text) from None


def _check_text(text: str) -> str:
    """Checks on the raw text, before the Python parser sees it; returns it on one line."""
    if not text.strip():
        raise ExpressionError("empty expression", text)
    if len(text) > limits.MAX_LENGTH:
        raise ExpressionError(
            f"expression too long ({len(text)} characters; at most {limits.MAX_LENGTH})", text
        )
    if not text.isascii():
        # Python would NFKC-normalise look-alike identifiers, so refuse them here.
        char = next(c for c in text if ord(c) > 127)
        raise ExpressionError(f"non-ASCII character {char!r} (U+{ord(char):04X})", text)
    control = re.search(r"[\x00-\x08\x0b\x0c\x0e-\x1f\x7f]", text)
    if control:
        # Python reads a form feed as a space; none of these belongs in an expression.
        code = ord(control.group())
        raise ExpressionError(f"control character U+{code:04X} is not allowed", text)
    if "#" in text:
        raise ExpressionError("comments ('#') are not allowed", text)
    if _count_parts(text) > limits.MAX_NODES:
        # Long chains a + b + ... can exhaust the Python parser's recursion limit.
        raise ExpressionError(f"expression too large (more than {limits.MAX_NODES} parts)", text)
    if _bracket_depth(text) > limits.MAX_DEPTH:
        raise ExpressionError(
            f"expression nested too deeply (more than {limits.MAX_DEPTH} levels)", text
        )
    for token in re.findall(r"[\w.]+", text):
        if token[0] in "0123456789." and len(token) > limits.MAX_DIGITS:
            raise ExpressionError(
                f"number literal too long (more than {limits.MAX_DIGITS} digits)", text
            )
    # Line breaks (from multi-line TOML strings) are plain spaces here; the length is kept.
    return text.replace("\r", " ").replace("\n", " ").strip()


def _count_parts(text: str) -> int:
    """About how many names, numbers and operators ``text`` has (never many more than its nodes)."""
    return len(re.findall(r"[\w.]+|\*\*|[-+*/]", text))


def _bracket_depth(text: str) -> int:
    """The deepest nesting of brackets in ``text`` (deep nesting can crash the Python parser)."""
    depth = deepest = 0
    for char in text:
        if char in "([{":
            depth += 1
            deepest = max(deepest, depth)
        elif char in ")]}":
            depth -= 1
    return deepest


def _parse_tree(flat: str, text: str) -> ast.Expression:
    """The Python syntax tree of ``flat``, or ExpressionError. Python's own warnings on
    the text (``2and M1``: "invalid decimal literal") are not the user's concern: the
    text is refused, or read, by our rules alone."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", SyntaxWarning)
            return ast.parse(flat, mode="eval")
    except (RecursionError, MemoryError):
        raise ExpressionError(
            f"expression nested too deeply (more than {limits.MAX_DEPTH} levels)", text
        ) from None
    except (SyntaxError, ValueError):
        raise ExpressionError("not a valid expression", text) from None


def _check_node_count(tree: ast.Expression, text: str) -> None:
    """Refuse trees with more than MAX_NODES expression nodes (ast.walk is iterative)."""
    count = sum(1 for node in ast.walk(tree) if isinstance(node, ast.expr))
    if count > limits.MAX_NODES:
        raise ExpressionError(f"expression too large (more than {limits.MAX_NODES} parts)", text)


_REFUSED_NODES: dict[type, str] = {
    ast.Attribute: "attribute access is not allowed",
    ast.Subscript: "indexing is not allowed",
    ast.Slice: "indexing is not allowed",
    ast.Lambda: "lambdas are not allowed",
    ast.ListComp: "comprehensions are not allowed",
    ast.SetComp: "comprehensions are not allowed",
    ast.DictComp: "comprehensions are not allowed",
    ast.GeneratorExp: "comprehensions are not allowed",
    ast.NamedExpr: "':=' is not allowed",
    ast.Compare: "comparisons are not allowed",
    ast.BoolOp: "'and' and 'or' are not allowed",
    ast.IfExp: "conditional expressions are not allowed",
    ast.List: "lists are not allowed",
    ast.Tuple: "tuples are not allowed",
    ast.Set: "sets are not allowed",
    ast.Dict: "dictionaries are not allowed",
    ast.JoinedStr: "strings are not allowed",
    ast.FormattedValue: "strings are not allowed",
    ast.Starred: "'*' unpacking is not allowed",
    ast.Await: "'await' is not allowed",
    ast.Yield: "'yield' is not allowed",
    ast.YieldFrom: "'yield' is not allowed",
}

_REFUSED_OPERATORS: dict[type, str] = {
    ast.BitXor: "'^' is not a power; use '**'",
    ast.Mod: "'%' is not allowed",
    ast.FloorDiv: "'//' is not allowed",
    ast.MatMult: "'@' is not allowed",
    ast.LShift: "'<<' is not allowed",
    ast.RShift: "'>>' is not allowed",
    ast.BitOr: "'|' is not allowed",
    ast.BitAnd: "'&' is not allowed",
    ast.Not: "'not' is not allowed",
    ast.Invert: "'~' is not allowed",
}

_DECIMAL = re.compile(r"(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?")


class _Builder:
    """One walk over a syntax tree, building the sympy expression bottom-up.

    Every ``build`` returns (expression, size), where size bounds the digits of
    every number in the expression. sympy computes with numbers as it builds
    (2**1000 is evaluated, 1/2 + 1/3 is added up, sqrt(12) is factored), so each
    step checks first that the numbers it would make stay small.
    """

    def __init__(self, flat: str, text: str, ns: Namespace, budget: ParseBudget):
        self.flat = flat
        self.text = text
        self.ns = ns
        self.budget = budget
        self.diff_work = 0

    def fail(self, message: str) -> ExpressionError:
        return ExpressionError(message, self.text)

    def build(self, node: ast.AST, depth: int) -> tuple[sp.Expr, int]:
        """Dispatch on the node type; refuse anything not in the whitelist."""
        if depth > limits.MAX_DEPTH:
            raise self.fail(f"expression nested too deeply (more than {limits.MAX_DEPTH} levels)")
        if isinstance(node, ast.Constant):
            return self.constant(node)
        if isinstance(node, ast.Name):
            return self.name(node), 0
        if isinstance(node, ast.BinOp):
            return self.binary(node, depth)
        if isinstance(node, ast.UnaryOp):
            return self.unary(node, depth)
        if isinstance(node, ast.Call):
            return self.call(node, depth)
        raise self.fail(_REFUSED_NODES.get(type(node), f"{type(node).__name__} is not allowed"))

    # ----------------------------------------------------------------- leaves

    def constant(self, node: ast.Constant) -> tuple[sp.Expr, int]:
        """A number literal, made exact; every other literal is refused."""
        value = node.value
        if isinstance(value, bool):
            raise self.fail("booleans are not allowed")
        if value is None:
            raise self.fail("None is not allowed")
        if value is Ellipsis:
            raise self.fail("'...' is not allowed")
        if isinstance(value, str | bytes):
            raise self.fail("strings are not allowed")
        if isinstance(value, complex):
            raise self.fail("complex numbers are not allowed")
        if not isinstance(value, int | float):
            raise self.fail(f"{value!r} is not allowed")
        # One line of ASCII, so the column offsets index the text directly.
        number = self.exact_number(self.flat[node.col_offset : node.end_col_offset])
        return number, _digits(number)

    def exact_number(self, literal: str) -> sp.Rational:
        """The exact rational a decimal literal denotes: 0.1 -> 1/10, 1e-3 -> 1/1000."""
        too_long = f"number literal too long (more than {limits.MAX_DIGITS} digits)"
        literal = literal.replace("_", "")
        if len(literal) > limits.MAX_DIGITS:
            raise self.fail(too_long)
        if literal[:2].lower() in ("0x", "0o", "0b"):
            return sp.Integer(int(literal, 0))
        match = _DECIMAL.fullmatch(literal)
        if match is None:
            raise self.fail("not a valid expression")
        whole, fraction, exponent = match.group(1), match.group(2) or "", match.group(3) or "0"
        if abs(int(exponent)) > limits.MAX_DIGITS:
            raise self.fail(too_long)
        mantissa = sp.Integer(int(whole + fraction or "0"))
        return mantissa * sp.Rational(10) ** (int(exponent) - len(fraction))

    def name(self, node: ast.Name) -> sp.Expr:
        """A variable, constant, declared parameter or definition (its expression)."""
        name = node.id
        for table in (self.ns.state, CONSTANTS, self.ns.parameters):
            if name in table:
                return table[name]
        if name in self.ns.definitions:
            expr, parts = self.ns.definitions[name]
            self.budget.spend("parts", parts, self.text)
            return expr
        if name in FUNCTIONS or name == "diff":
            raise self.fail(f"'{name}' is a function; call it as {name}(...)")
        if name in self.ns.functions:
            raise self.fail(f"'{name}' is a function; call it as {self.declared_call(name)}")
        candidates = [*self.ns.state, *CONSTANTS, *self.ns.parameters, *self.ns.definitions]
        hint = _suggestion(name, candidates) or "declare it under [parameters]"
        raise self.fail(f"unknown name {_show(name)} ({hint})")

    def declared_call(self, name: str) -> str:
        """How a declared function must be called, e.g. ``a(s)``."""
        _, args = self.ns.functions[name]
        return f"{name}({', '.join(map(str, args))})"

    # ------------------------------------------------------------- operations

    def unary(self, node: ast.UnaryOp, depth: int) -> tuple[sp.Expr, int]:
        """Unary minus and plus."""
        if not isinstance(node.op, ast.USub | ast.UAdd):
            raise self.fail(_REFUSED_OPERATORS[type(node.op)])
        operand, size = self.build(node.operand, depth + 1)
        return (-operand if isinstance(node.op, ast.USub) else operand), size

    def binary(self, node: ast.BinOp, depth: int) -> tuple[sp.Expr, int]:
        """+ - * / **; chains of + - and of * / are built flat, without nesting."""
        op = node.op
        if isinstance(op, ast.Add | ast.Sub):
            return self.sum(node, depth)
        if isinstance(op, ast.Mult | ast.Div):
            return self.product(node, depth)
        if isinstance(op, ast.Pow):
            return self.power(node, depth)
        raise self.fail(_REFUSED_OPERATORS.get(type(op), f"{type(op).__name__} is not allowed"))

    def chain(
        self, node: ast.AST, ops: tuple[type, ...]
    ) -> list[tuple[ast.operator | None, ast.AST]]:
        """The operands of a left-associative chain a op b op c ..., left to right (the
        first operand's operator is None)."""
        items: list[tuple[ast.operator | None, ast.AST]] = []
        while isinstance(node, ast.BinOp) and isinstance(node.op, ops):
            items.append((node.op, node.right))
            node = node.left
        items.append((None, node))
        return items[::-1]

    def sum(self, node: ast.BinOp, depth: int) -> tuple[sp.Expr, int]:
        """a + b - c ..., as one sympy Add."""
        terms, size = [], 0
        for op, operand in self.chain(node, (ast.Add, ast.Sub)):
            term, term_size = self.build(operand, depth + 1)
            terms.append(-term if isinstance(op, ast.Sub) else term)
            size = max(size, term_size)
        # Adding fractions multiplies their denominators.
        denominators = {
            getattr(arg.as_coeff_Mul()[0], "q", 1)
            for term in terms
            for arg in sp.Add.make_args(term)
        }
        growth = sum(2 * _digits(sp.Integer(q)) for q in denominators if q != 1)
        size = self.bounded(size + len(str(len(terms))) + growth)
        return sp.Add(*terms), size

    def product(self, node: ast.BinOp, depth: int) -> tuple[sp.Expr, int]:
        """a * b / c ..., as one sympy Mul."""
        factors, size = [], 0
        for op, operand in self.chain(node, (ast.Mult, ast.Div)):
            factor, factor_size = self.build(operand, depth + 1)
            if isinstance(op, ast.Div):
                factor = self.checked(sp.Pow(factor, -1))
            factors.append(factor)
            size = max(size, factor_size)
        # Multiplying multiplies the coefficients, and the numbers under equal roots.
        self.check_root(sum(_root_digits(f) for f in factors))
        size = self.bounded(size + sum(_coeff_digits(f) for f in factors))
        return sp.Mul(*factors), size

    def power(self, node: ast.BinOp, depth: int) -> tuple[sp.Expr, int]:
        """base ** exponent, with the exponent and the numbers made bounded first."""
        base, base_size = self.build(node.left, depth + 1)
        exponent, exponent_size = self.build(node.right, depth + 1)
        if exponent.is_Rational:
            size = max(base_size, self.power_digits(base, exponent))
        else:
            size = base_size + exponent_size
        inner_base, inner_exponent = base.as_base_exp()
        if inner_base is sp.E:
            # E**x and exp(x)**y are exp(x*y), which sympy evaluates like exp().
            size = max(size, self.exp_log_digits(inner_exponent * exponent))
        return self.checked(sp.Pow(base, exponent)), size

    def power_digits(self, base: sp.Expr, exponent: sp.Rational) -> int:
        """How many digits the numbers sympy computes for base**exponent may have.

        Refuses large exponents, and roots of large numbers (sympy factors those).
        """
        if abs(exponent.p) > limits.MAX_EXPONENT * exponent.q:
            raise self.fail(f"exponent too large (at most {limits.MAX_EXPONENT} in absolute value)")
        if exponent.q > limits.MAX_DENOMINATOR:
            raise self.fail(f"exponent denominator too large (at most {limits.MAX_DENOMINATOR})")
        digits = _number_digits(base)
        if exponent.q > 1:
            self.check_root(digits)
            self.budget.spend("root_digits", digits, self.text)
        return self.bounded(digits * max(1, math.ceil(abs(exponent))))

    def check_root(self, digits: int) -> None:
        """Refuse roots of numbers with more than MAX_ROOT_DIGITS digits."""
        if digits > limits.MAX_ROOT_DIGITS:
            raise self.fail(
                "number too large for a root "
                f"(it could have more than {limits.MAX_ROOT_DIGITS} digits)"
            )

    def bounded(self, size: int) -> int:
        """``size``, after checking that numbers of that many digits are allowed."""
        if size > limits.MAX_RESULT_DIGITS:
            raise self.fail(
                f"number too large (it could have more than {limits.MAX_RESULT_DIGITS} digits)"
            )
        return size

    def checked(self, expr: sp.Expr) -> sp.Expr:
        """Refuse results that are infinite, undefined or not real (1/0, log(0), sqrt(-1))."""
        if expr.has(*_UNDEFINED):
            raise self.fail("division by zero or an undefined value")
        if expr.has(sp.I):
            raise self.fail("the expression is not real (it involves the imaginary unit)")
        if expr.find(_is_complex_root):
            raise self.fail("the expression is not real (a fractional power of a negative number)")
        return expr

    def exp_log_digits(self, arg: sp.Expr) -> int:
        """sympy turns exp(c*log(a) + ...) into a**c * ...: bound it like a product of powers."""
        digits = roots = 0
        for term in sp.Add.make_args(arg):
            coeff, rest = term.as_coeff_Mul()
            logs = [f for f in sp.Mul.make_args(rest) if isinstance(f, sp.log)]
            if len(logs) == 1 and coeff.is_Rational:
                digits += self.power_digits(logs[0].args[0], coeff)
                roots += _number_digits(logs[0].args[0]) if coeff.q > 1 else 0
        self.check_root(roots)
        return self.bounded(digits)

    # ------------------------------------------------------------------ calls

    def call(self, node: ast.Call, depth: int) -> tuple[sp.Expr, int]:
        """A call of an elementary function, of ``diff`` or of a declared function."""
        func = node.func
        if isinstance(func, ast.Attribute):
            raise self.fail(_REFUSED_NODES[ast.Attribute])
        if not isinstance(func, ast.Name):
            raise self.fail("only named functions can be called")
        if any(keyword.arg is None for keyword in node.keywords):
            raise self.fail("'**' unpacking is not allowed")
        if node.keywords:
            raise self.fail("keyword arguments are not allowed")
        if any(isinstance(arg, ast.Starred) for arg in node.args):
            raise self.fail(_REFUSED_NODES[ast.Starred])
        name = func.id
        if name in FUNCTIONS:
            return self.elementary(name, node.args, depth)
        if name == "diff":
            return self.derivative(node.args, depth)
        if name in self.ns.functions:
            return self.declared(name, node.args), 0
        candidates = [*FUNCTIONS, "diff", *self.ns.functions]
        hint = _suggestion(name, candidates)
        raise self.fail(f"unknown function {_show(name)}" + (f" ({hint})" if hint else ""))

    def elementary(self, name: str, args: list[ast.expr], depth: int) -> tuple[sp.Expr, int]:
        """sqrt, exp, log, ... of one argument."""
        if len(args) != 1:
            raise self.fail(f"{name}() takes exactly one argument ({len(args)} given)")
        arg, size = self.build(args[0], depth + 1)
        if name == "sqrt":
            size = max(size, self.power_digits(arg, sp.Rational(1, 2)))
        if name == "exp":
            size = max(size, self.exp_log_digits(arg))
        if name in ("sin", "cos", "tan"):
            coeff, rest = arg.as_coeff_Mul()
            if rest is sp.pi and coeff.is_Rational and coeff.q > limits.MAX_TRIG_DENOMINATOR:
                return FUNCTIONS[name](arg, evaluate=False), size
        return self.checked(FUNCTIONS[name](arg)), size

    def declared(self, name: str, args: list[ast.expr]) -> sp.Expr:
        """A declared function, called with exactly its declared argument names."""
        func, params = self.ns.functions[name]
        given = [arg.id if isinstance(arg, ast.Name) else None for arg in args]
        if given != [str(p) for p in params]:
            raise self.fail(f"'{name}' must be called as {self.declared_call(name)}")
        return func(*params)

    def derivative(self, args: list[ast.expr], depth: int) -> tuple[sp.Expr, int]:
        """diff(expr, var): the total derivative on R^6, or d/ds of a function of s alone."""
        if len(args) != 2:
            raise self.fail("diff takes two arguments: diff(expression, variable)")
        var = args[1]
        state = self.ns.state
        if not (isinstance(var, ast.Name) and var.id in state):
            raise self.fail(f"the second argument of diff must be one of {self.ns.variable_list()}")
        expr, size = self.build(args[0], depth + 1)
        work = _diff_work(expr, limits.MAX_DIFF_WORK - self.diff_work)
        self.diff_work += work
        if self.diff_work > limits.MAX_DIFF_WORK:
            raise self.fail("expression too large to differentiate")
        self.budget.spend("diff_work", work, self.text)
        symbol = state[var.id]
        if not self.ns.paper_state:
            return sp.diff(expr, symbol), size + 10
        if symbol != s:
            return total_diff(expr, symbol), size + 10
        if expr.free_symbols & set(STATE):
            raise self.fail(
                "diff(..., s) needs an expression that depends on the variables through s alone"
            )
        return sp.diff(expr, s), size + 10


def _is_complex_root(expr: sp.Basic) -> bool:
    """Whether ``expr`` is (-1)**q for a fraction q: sympy's complex root of -1."""
    if not (expr.is_Pow and expr.base is sp.S.NegativeOne):
        return False
    return expr.exp.is_Rational and not expr.exp.is_Integer


def _diff_work(expr: sp.Expr, limit: int) -> int:
    """The cost of differentiating ``expr`` (see MAX_DIFF_WORK), counted up to past ``limit``."""
    work = 0
    for node in sp.preorder_traversal(expr):
        work += len(node.args) ** 2 if node.is_Mul else 1
        if work > limit:
            break
    return work


def _coeff_digits(expr: sp.Expr) -> int:
    """Digits of the rational coefficient of ``expr`` (0 for 1 and -1)."""
    coeff = expr.as_coeff_Mul()[0]
    return _digits(coeff) if coeff.is_Rational and abs(coeff) != 1 else 0


def _root_digits(expr: sp.Expr) -> int:
    """Digits of the numbers under roots among the factors of ``expr``."""
    return sum(
        _digits(f.base)
        for f in sp.Mul.make_args(expr)
        if f.is_Pow and f.base.is_Rational and f.exp.is_Rational and not f.exp.is_Integer
    )


def _number_digits(expr: sp.Expr) -> int:
    """Digits of the numbers that ``expr**n`` raises to the n-th power, per unit of n."""
    total = 0
    for f in sp.Mul.make_args(expr):
        if f.is_Rational:
            total += _digits(f)
        elif f.is_Pow and f.base.is_Rational and f.exp.is_Rational:
            total += _digits(f.base) * max(1, math.ceil(abs(f.exp)))
    return total


def _digits(number: sp.Rational) -> int:
    """About how many decimal digits numerator and denominator of ``number`` have."""
    bits = abs(number.p).bit_length() + number.q.bit_length()
    return int(bits * math.log10(2)) + 1


def _suggestion(name: str, candidates: list[str]) -> str:
    """'did you mean ...?' for the closest candidate, or '' when none is close."""
    close = difflib.get_close_matches(name, candidates, n=1)
    return f"did you mean {close[0]!r}?" if close else ""


def _show(name: str, limit: int = 40) -> str:
    """A user-written name, quoted and cut to a readable length."""
    return repr(name if len(name) <= limit else name[: limit - 3] + "...")
