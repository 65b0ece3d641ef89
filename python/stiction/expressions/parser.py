"""Token access and the expression grammar of the Modelica subset, shared by the .mo file
parser (``parser``) and the parser of one expression (a derived variable's binding).

It works on token indices: ``self.i`` is the current token, ``kinds``/``texts`` the lexer's
parallel lists (the hot paths read them into locals and test texts directly).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TypeVar

from stiction.expressions.ast import Array, BinOp, Call, Expr, IfExpr, Literal, Matrix, Ref, Unary
from stiction.expressions.lexer import ModelicaError, Pos, Tokens, tokenize

__all__ = ["ExpressionParser", "parse_expression"]

T = TypeVar("T")
# Every walk over an expression (evaluation, dependency checks, export) recurses once per
# level, and a chain like 1+1+…+1 is as deep as it is long: deeper is an error, not a crash.
MAX_DEPTH = 200

_RELATIONS = ("<", "<=", ">", ">=", "==", "<>")
_AFTER_VALUE = frozenset((",", ")", ";", "}", "]"))


class ExpressionParser:
    """Tokens with a cursor, and expressions read from them."""

    def __init__(self, tokens: Tokens) -> None:
        self.tokens = tokens
        self.kinds = tokens.kinds
        self.texts = tokens.texts
        self.last = len(tokens.texts) - 1  # the end-of-file token
        self.i = 0
        self.depth = 0  # of the expression tree being read, at the cursor

    def guarded(self, read: Callable[[], T]) -> T:
        """``read()``, with nesting too deep for Python's stack (``((((…``, ``a(b(c(…``) as
        an error at the token where it got too deep: the grammar is recursive descent."""
        try:
            return read()
        except RecursionError:
            raise self.fail("nested too deeply to read") from None

    # --- tokens ------------------------------------------------------------------------
    def number(self, i: int) -> Literal:
        """The number token ``i``: an Integer within 64 bits or a finite Real, else a located
        error (a literal of 400 digits would overflow the float every parameter becomes)."""
        text = self.texts[i]
        # past 19 digits an Integer is out of range; Python refuses to convert 4300 at all
        if text.isdigit() and len(text.lstrip("0")) > 19:
            raise self.fail(f"the Integer literal {text[:24]}... is out of range", i)
        value: int | float = int(text) if text.isdigit() else float(text)
        if isinstance(value, int) and value >= 2**63:
            raise self.fail(f"the Integer literal {text[:24]}... is out of range", i)
        if value == math.inf:
            raise self.fail(f"the number {text[:24]} is too large for a Real", i)
        return Literal(value, self.pos(i))

    def pos(self, i: int | None = None) -> Pos:
        return Pos.at(self.tokens, self.i if i is None else i)

    def peek(self) -> str:
        return self.texts[min(self.i + 1, self.last)]

    def at(self, *texts: str) -> bool:
        # no identifier, number or string is spelled like an operator or keyword
        return self.texts[self.i] in texts

    def take(self) -> int:
        self.i += 1
        return self.i - 1

    def accept(self, text: str) -> bool:
        if self.texts[self.i] == text:
            self.i += 1
            return True
        return False

    def fail(self, message: str, i: int | None = None) -> ModelicaError:
        return ModelicaError(self.pos(i), message)

    def found(self) -> str:
        return "end of file" if self.kinds[self.i] == "eof" else f"'{self.texts[self.i]}'"

    def expect(self, text: str, context: str = "") -> int:
        i = self.i
        if self.texts[i] != text:
            where = f" {context}" if context else ""
            raise self.fail(f"syntax error: expected '{text}'{where}, found {self.found()}")
        self.i = i + 1
        return i

    def ident(self, what: str = "a name") -> int:
        i = self.i
        if self.kinds[i] != "ident":
            raise self.fail(f"syntax error: expected {what}, found {self.found()}")
        self.i = i + 1
        return i

    def name(self, what: str = "a name") -> tuple[str, Pos]:
        first = self.ident(what)
        texts, kinds, i = self.texts, self.kinds, first + 1
        if texts[i] != ".":  # the common case: one identifier
            return texts[first], Pos.at(self.tokens, first)
        parts = [texts[first]]
        while texts[i] == "." and kinds[i + 1] == "ident":
            parts.append(texts[i + 1])
            i += 2
        self.i = i
        return ".".join(parts), Pos.at(self.tokens, first)

    def string_comment(self) -> str:
        kinds, texts, i = self.kinds, self.texts, self.i
        if kinds[i] != "string":
            return ""
        parts = []
        while kinds[i] == "string":
            parts.append(texts[i][1:-1])
            i += 1
            if texts[i] == "+":
                i += 1
        self.i = i
        return "".join(parts).replace('\\"', '"')

    # --- expressions ------------------------------------------------------------------
    def expression(self) -> Expr:
        saved = self.depth  # an error ends the parse, so no restoring on the way out
        self.deeper()
        expr = self._expression()
        self.depth = saved
        return expr

    def deeper(self) -> None:
        """One level deeper in the expression tree: a nested expression or a chained operator."""
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self.fail(f"expression deeper than {MAX_DEPTH} levels (operators chained or nested)")

    def _expression(self) -> Expr:
        i = self.i
        kind, text = self.kinds[i], self.texts[i]
        if (
            kind != "eof" and self.texts[i + 1] in _AFTER_VALUE
        ):  # fast paths for a lone value: J=1, fixed=true, k=T2
            if kind == "number":
                self.i = i + 1
                return self.number(i)
            if kind == "ident":
                self.i = i + 1
                return Ref(text, Pos.at(self.tokens, i))
            if text in ("true", "false"):
                self.i = i + 1
                return Literal(text == "true", Pos.at(self.tokens, i))
        if text == "if":
            start = self.take()
            cond = self.expression()
            self.expect("then", "in the if-expression")
            then = self.expression()
            if self.at("elseif"):
                self.texts[self.i] = "if"  # the rest reads as a nested if-expression
                return IfExpr(cond, then, self.expression(), self.pos(start))
            self.expect("else", "in the if-expression")
            return IfExpr(cond, then, self.expression(), self.pos(start))
        return self.logical("or")

    def logical(self, op: str) -> Expr:
        sub = (lambda: self.logical("and")) if op == "or" else self.negation
        left = sub()
        while self.texts[self.i] == op:
            token = self.take()
            self.deeper()
            left = BinOp(op, left, sub(), self.pos(token))
        return left

    def negation(self) -> Expr:
        if self.texts[self.i] == "not":
            token = self.take()
            return Unary("not", self.relation(), self.pos(token))
        return self.relation()

    def relation(self) -> Expr:
        left = self.arithmetic()
        if self.texts[self.i] in _RELATIONS:
            token = self.take()
            return BinOp(self.texts[token], left, self.arithmetic(), self.pos(token))
        return left

    def arithmetic(self) -> Expr:
        texts = self.texts
        if texts[self.i] in ("-", "+"):
            token = self.take()
            left: Expr = Unary(texts[token], self.term(), self.pos(token))
        else:
            left = self.term()
        while texts[self.i] in ("+", "-", ".+", ".-"):
            token = self.take()
            self.deeper()
            left = BinOp(texts[token].lstrip("."), left, self.term(), self.pos(token))
        return left

    def term(self) -> Expr:
        texts = self.texts
        left = self.factor()
        while texts[self.i] in ("*", "/", ".*", "./"):
            token = self.take()
            self.deeper()
            left = BinOp(texts[token].lstrip("."), left, self.factor(), self.pos(token))
        return left

    def factor(self) -> Expr:
        base = self.primary()
        if self.texts[self.i] in ("^", ".^"):
            token = self.take()
            if self.at("-", "+"):  # 2^-1 is not Modelica, but a unary sign here is harmless
                sign = self.take()
                return BinOp(
                    "^", base, Unary(self.texts[sign], self.primary(), self.pos(sign)), self.pos(token)
                )
            return BinOp("^", base, self.primary(), self.pos(token))
        return base

    def primary(self) -> Expr:
        i = self.i
        kind, text = self.kinds[i], self.texts[i]
        if kind == "number":
            self.i = i + 1
            return self.number(i)
        if kind == "string":
            return Literal(self.string_comment(), self.pos(i))
        if text in ("true", "false"):
            self.i = i + 1
            return Literal(text == "true", self.pos(i))
        if text == "(":
            self.i = i + 1
            inner = self.expression()
            self.expect(")", "closing the parenthesis")
            return inner
        if text == "{":
            return self.array()
        if text == "[":
            return self.matrix()
        if kind == "ident" or text in ("der", "initial"):
            return self.name_or_call()
        raise self.fail(f"syntax error: expected an expression, found {self.found()}")

    def name_or_call(self) -> Expr:
        if self.kinds[self.i] == "kw":  # der(…), initial()
            first = self.take()
            name, pos = self.texts[first], self.pos(first)
        else:
            name, pos = self.name()
        if self.texts[self.i] == "(":
            return self.call(name, pos)
        ref = Ref(name, pos)
        if self.texts[self.i] == "[":
            ref.subscripts = self.subscripts()
        while self.at(".") and self.kinds[min(self.i + 1, self.last)] == "ident":  # a[1].b
            self.i += 2
            ref.name += "." + self.texts[self.i - 1]
        return ref

    def subscripts(self) -> list[Expr]:
        subs: list[Expr] = []
        if self.accept("["):
            subs.append(self.expression())
            while self.accept(","):
                subs.append(self.expression())
            self.expect("]", "closing the subscript")
        return subs

    def call(self, func: str, pos: Pos) -> Call:
        self.expect("(")
        call = Call(func, [], {}, pos)
        while not self.at(")"):
            if self.kinds[self.i] == "ident" and self.peek() == "=":
                key = self.texts[self.take()]
                self.take()
                call.kwargs[key] = self.expression()
            else:
                call.args.append(self.expression())
            if not self.accept(","):
                break
        self.expect(")", f"closing the call of '{func}'")
        return call

    def array(self) -> Array:
        start = self.expect("{")
        items: list[Expr] = []
        while not self.at("}"):
            items.append(self.expression())
            if not self.accept(","):
                break
        self.expect("}", "closing the array")
        return Array(items, self.pos(start))

    def matrix(self) -> Matrix:
        start = self.expect("[")
        rows: list[list[Expr]] = [[self.expression()]]
        while self.at(",", ";"):
            if self.texts[self.take()] == ";":
                rows.append([])
            rows[-1].append(self.expression())
        self.expect("]", "closing the matrix")
        return Matrix(rows, self.pos(start))

    def component_ref(self) -> Ref:
        i, kinds, texts = self.i, self.kinds, self.texts
        if kinds[i] != "ident":
            raise self.fail(f"syntax error: expected a connector such as 'J1.flange_a', found {self.found()}")
        if texts[i + 1] == "." and kinds[i + 2] == "ident" and texts[i + 3] in (",", ")"):  # J1.flange_a
            self.i = i + 3
            return Ref(f"{texts[i]}.{texts[i + 2]}", Pos.at(self.tokens, i))
        expr = self.name_or_call()
        if not isinstance(expr, Ref):
            raise self.fail("syntax error: a connector, not a call, is expected in connect(…)")
        return expr


def parse_expression(text: str, source: str = "<expression>") -> Expr:
    """Parse one Modelica expression (a parameter's or a derived variable's binding)."""
    parser = ExpressionParser(tokenize(text, source))
    expr = parser.guarded(parser.expression)
    if parser.kinds[parser.i] != "eof":
        raise parser.fail(f"syntax error: unexpected {parser.found()} after the expression")
    return expr
