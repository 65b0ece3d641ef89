"""Recursive-descent parser for the Modelica subset stiction reads (see docs/modelica.md).

It parses what MSL-style models contain: ``within``, classes (several per file, nested in
packages), ``import``/``extends`` clauses, declarations with modifiers, ``connect``
equations and annotations (parsed completely, so a malformed one is a syntax error, and
kept only at class level, where ``experiment`` lives). Anything else of Modelica is refused
at its position, saying what it is and what is supported.
"""

from __future__ import annotations

from .ast import (
    Array,
    BinOp,
    Call,
    ClassDef,
    Connect,
    Declaration,
    Expr,
    IfExpr,
    Import,
    Literal,
    Matrix,
    Modification,
    Ref,
    StoredDefinition,
    Unary,
)
from .lexer import ModelicaError, Pos, Token, tokenize

__all__ = ["SUPPORTED", "parse", "parse_expression"]

SUPPORTED = (
    "supported: model/block/package classes with import and extends Modelica.Icons.* clauses, "
    "parameter and component declarations with modifiers, variables with a binding, "
    "connect equations and annotations"
)
_CLASS_KINDS = ("model", "block", "class", "package")
_UNSUPPORTED_PREFIXES = ("replaceable", "redeclare", "inner", "outer", "flow", "stream")
_TYPE_PREFIXES = ("parameter", "constant", "input", "output", "discrete")
_RELATIONS = ("<", "<=", ">", ">=", "==", "<>")
_AFTER_VALUE = frozenset((",", ")", ";", "}", "]"))


def parse(text: str, source: str = "<modelica>") -> StoredDefinition:
    """Parse a whole ``.mo`` file; raises ModelicaError at the first problem."""
    return _Parser(tokenize(text, source)).stored_definition()


class _Parser:
    def __init__(self, tokens: list[Token]) -> None:
        self.tokens = tokens
        self.i = 0

    # --- token helpers ----------------------------------------------------------------
    @property
    def tok(self) -> Token:
        return self.tokens[self.i]

    def peek(self, ahead: int = 1) -> Token:
        return self.tokens[min(self.i + ahead, len(self.tokens) - 1)]

    def at(self, *texts: str) -> bool:
        # no identifier, number or string is spelled like an operator or keyword
        return self.tokens[self.i].text in texts

    def take(self) -> Token:
        token = self.tok
        self.i += 1
        return token

    def accept(self, text: str) -> bool:
        if self.at(text):
            self.i += 1
            return True
        return False

    def fail(self, message: str, token: Token | None = None) -> ModelicaError:
        return ModelicaError((token or self.tok).pos, message)

    def found(self) -> str:
        t = self.tok
        return "end of file" if t.kind == "eof" else f"'{t.text}'"

    def expect(self, text: str, context: str = "") -> Token:
        if not self.at(text):
            where = f" {context}" if context else ""
            raise self.fail(f"syntax error: expected '{text}'{where}, found {self.found()}")
        return self.take()

    def ident(self, what: str = "a name") -> Token:
        if self.tok.kind != "ident":
            raise self.fail(f"syntax error: expected {what}, found {self.found()}")
        return self.take()

    def name(self, what: str = "a name") -> tuple[str, Pos]:
        first = self.ident(what)
        tokens, i = self.tokens, self.i
        if tokens[i].text != ".":  # the common case: one identifier
            return first.text, first.pos
        parts = [first.text]
        while tokens[i].text == "." and tokens[i + 1].kind == "ident":
            parts.append(tokens[i + 1].text)
            i += 2
        self.i = i
        return ".".join(parts), first.pos

    def string_comment(self) -> str:
        parts = []
        while self.tok.kind == "string":
            parts.append(self.take().text[1:-1])
            self.accept("+")
        return "".join(parts).replace('\\"', '"')

    # --- classes ----------------------------------------------------------------------
    def stored_definition(self) -> StoredDefinition:
        within = ""
        if self.accept("within"):
            if not self.at(";"):
                within = self.name("a package name after 'within'")[0]
            self.expect(";", "after the within clause")
        classes = []
        while self.tok.kind != "eof":
            self.accept("final")
            classes.append(self.class_definition())
            self.expect(";", f"after 'end {classes[-1].name}'")
        if not classes:
            raise self.fail("no model in the text: expected 'model Name … end Name;'")
        return StoredDefinition(within, classes)

    def class_definition(self) -> ClassDef:
        self.accept("encapsulated")
        self.accept("partial")
        if not self.at(*_CLASS_KINDS):
            if self.tok.kind == "kw" and self.tok.text in ("function", "record", "connector", "type"):
                raise self.fail(f"unsupported class kind '{self.tok.text}'; {SUPPORTED}")
            raise self.fail(f"syntax error: expected 'model', 'block' or 'package', found {self.found()}")
        kind = self.take().text
        head = self.ident(f"the {kind}'s name")
        if self.at("="):
            raise self.fail(f"unsupported short class definition '{kind} {head.text} = …'; {SUPPORTED}")
        cls = ClassDef(kind, head.text, head.pos, description=self.string_comment())
        self.composition(cls)
        end = self.expect("end", f"or a declaration in {kind} '{cls.name}'")
        closing = self.ident(f"'{cls.name}' after 'end'") if self.tok.kind == "ident" else None
        if closing is None or closing.text != cls.name:
            got = f"'end {closing.text}'" if closing else "'end' alone"
            raise ModelicaError(
                (closing or end).pos, f"{kind} '{cls.name}' (line {head.pos.line}) closed by {got}"
            )
        return cls

    def composition(self, cls: ClassDef) -> None:
        while True:
            if self.at("public", "protected"):
                self.take()
            elif self.at("equation"):
                self.take()
                self.equations(cls)
            elif self.at("initial") and self.peek().text == "equation":
                raise self.fail(f"unsupported 'initial equation' section; {SUPPORTED}")
            elif self.at("algorithm") or (self.at("initial") and self.peek().text == "algorithm"):
                raise self.fail(f"unsupported algorithm section; {SUPPORTED}")
            elif self.at("annotation"):
                cls.annotation.extend(self.annotation())
                self.expect(";", "after the annotation")
            elif self.at("end") or self.tok.kind == "eof":
                return
            else:
                self.element(cls)

    def equations(self, cls: ClassDef) -> None:
        while not self.at("end", "annotation", "public", "protected", "equation", "algorithm", "initial"):
            if self.tok.kind == "eof":
                return
            start = self.tok
            if not self.accept("connect"):
                what = start.text if start.kind == "kw" else "equation"
                raise self.fail(
                    f"unsupported {what} '{self.statement_text()}'; only connect(…) "
                    f"equations are supported ({SUPPORTED})",
                    start,
                )
            self.expect("(", "after 'connect'")
            a = self.component_ref()
            self.expect(",", "between the two connectors of connect(…)")
            b = self.component_ref()
            self.expect(")", "closing connect(…)")
            self.string_comment()
            if self.at("annotation"):
                self.skip_annotation()
            self.expect(";", "after connect(…)")
            cls.connects.append(Connect(a, b, start.pos))

    def statement_text(self) -> str:
        parts, j = [], self.i
        while self.tokens[j].kind != "eof" and self.tokens[j].text != ";" and len(parts) < 8:
            parts.append(self.tokens[j].text)
            j += 1
        return " ".join(parts)

    # --- elements ---------------------------------------------------------------------
    def element(self, cls: ClassDef) -> None:
        if self.at("import"):
            cls.imports.append(self.import_clause())
        elif self.at("extends"):
            self.take()
            cls.extends.append(self.name("a class name after 'extends'"))
            if self.at("("):
                self.class_modification()
            if self.at("annotation"):
                self.skip_annotation()
        elif self.at(*_CLASS_KINDS, "encapsulated", "partial"):
            cls.classes.append(self.class_definition())
        else:
            self.accept("final")
            if self.at(*_UNSUPPORTED_PREFIXES):
                raise self.fail(f"unsupported '{self.tok.text}' element; {SUPPORTED}")
            cls.declarations.extend(self.component_clause())
        self.expect(";", "after the declaration")

    def import_clause(self) -> Import:
        start = self.take()
        if self.tok.kind == "ident" and self.peek().text == "=":
            alias = self.take().text
            self.take()
            target, _ = self.name("a class name")
            return Import(alias, target, False, start.pos)
        target, _ = self.name("a class name after 'import'")
        if self.accept(".*"):  # the lexer reads ".*" as one (element-wise) operator
            return Import(None, target, True, start.pos)
        if self.accept("."):
            if self.accept("*"):
                return Import(None, target, True, start.pos)
            raise self.fail(
                "unsupported import form; use 'import A.B;', 'import X = A.B;' or 'import A.B.*;'"
            )
        return Import(None, target, False, start.pos)

    def component_clause(self) -> list[Declaration]:
        prefix = ""
        while self.at(*_TYPE_PREFIXES):
            prefix = self.take().text if not prefix else prefix
        type_name, type_pos = self.name("a type or class name")
        if self.at("["):
            raise self.fail(f"unsupported array type '{type_name}[…]'; {SUPPORTED}")
        decls = [self.declaration(type_name, type_pos, prefix)]
        while self.accept(","):
            decls.append(self.declaration(type_name, type_pos, prefix))
        return decls

    def declaration(self, type_name: str, type_pos: Pos, prefix: str) -> Declaration:
        head = self.ident("a component name")
        if self.at("["):
            raise self.fail(f"unsupported array component '{head.text}[…]'; {SUPPORTED}")
        decl = Declaration(type_name, type_pos, head.text, head.pos, prefix)
        if self.at("("):
            decl.args = self.class_modification()
        if self.accept("=") or self.accept(":="):
            decl.binding = self.expression()
        if self.at("if"):
            raise self.fail(f"unsupported conditional component '{head.text} if …'; {SUPPORTED}")
        decl.description = self.string_comment()
        if self.at("annotation"):
            self.skip_annotation()
        return decl

    # --- modifications ----------------------------------------------------------------
    def class_modification(self) -> list[Modification]:
        self.expect("(")
        args: list[Modification] = []
        if not self.at(")"):
            args.append(self.argument())
            while self.accept(","):
                args.append(self.argument())
        self.expect(")", "closing the modifier list")
        return args

    def argument(self) -> Modification:
        while self.tokens[self.i].text in ("each", "final"):
            self.i += 1
        if self.at("redeclare", "replaceable"):
            raise self.fail(f"unsupported '{self.tok.text}' modifier; {SUPPORTED}")
        name, pos = self.name("a modifier name")
        mod = Modification(name, pos)
        text = self.tokens[self.i].text
        if text == "(":
            mod.args = self.class_modification()
            text = self.tokens[self.i].text
        if text in ("=", ":="):
            self.i += 1
            mod.value = self.expression()
        if self.tokens[self.i].kind == "string":
            mod.description = self.string_comment()
        return mod

    def annotation(self) -> list[Modification]:
        self.expect("annotation")
        return self.class_modification()

    def skip_annotation(self) -> None:
        """Skip a component's or connection's annotation (graphics only) by matching its
        brackets: most tokens of an MSL model are placement and line annotations."""
        self.expect("annotation")
        opening = self.expect("(", "after 'annotation'")
        closers = {"(": ")", "[": "]", "{": "}"}
        stack = [")"]
        tokens, i = self.tokens, self.i
        while stack:
            token = tokens[i]
            text = token.text
            if token.kind == "op":
                if text in closers:
                    stack.append(closers[text])
                elif text in (")", "]", "}") and text != stack.pop():
                    self.i = i
                    raise self.fail(f"syntax error: unbalanced '{text}' in the annotation")
            elif token.kind == "eof":
                raise ModelicaError(opening.pos, "syntax error: the annotation's '(' is never closed")
            i += 1
        self.i = i

    # --- expressions ------------------------------------------------------------------
    def expression(self) -> Expr:
        token = self.tok
        if token.kind == "number" and self.peek().text in _AFTER_VALUE:  # fast path: J=1
            self.i += 1
            return Literal(int(token.text) if token.text.isdigit() else float(token.text), token.pos)
        if self.at("if"):
            start = self.take()
            cond = self.expression()
            self.expect("then", "in the if-expression")
            then = self.expression()
            if self.at("elseif"):
                self.tokens[self.i] = self.tok._replace(kind="kw", text="if")
                return IfExpr(cond, then, self.expression(), start.pos)
            self.expect("else", "in the if-expression")
            return IfExpr(cond, then, self.expression(), start.pos)
        return self.logical("or")

    def logical(self, op: str) -> Expr:
        sub = (lambda: self.logical("and")) if op == "or" else self.negation
        left = sub()
        while self.at(op):
            token = self.take()
            left = BinOp(op, left, sub(), token.pos)
        return left

    def negation(self) -> Expr:
        if self.at("not"):
            token = self.take()
            return Unary("not", self.relation(), token.pos)
        return self.relation()

    def relation(self) -> Expr:
        left = self.arithmetic()
        if self.at(*_RELATIONS):
            token = self.take()
            return BinOp(token.text, left, self.arithmetic(), token.pos)
        return left

    def arithmetic(self) -> Expr:
        if self.at("-", "+"):
            token = self.take()
            left: Expr = Unary(token.text, self.term(), token.pos)
        else:
            left = self.term()
        while self.at("+", "-", ".+", ".-"):
            token = self.take()
            left = BinOp(token.text.lstrip("."), left, self.term(), token.pos)
        return left

    def term(self) -> Expr:
        left = self.factor()
        while self.at("*", "/", ".*", "./"):
            token = self.take()
            left = BinOp(token.text.lstrip("."), left, self.factor(), token.pos)
        return left

    def factor(self) -> Expr:
        base = self.primary()
        if self.at("^", ".^"):
            token = self.take()
            if self.at("-", "+"):  # 2^-1 is not Modelica, but a unary sign here is harmless
                sign = self.take()
                return BinOp("^", base, Unary(sign.text, self.primary(), sign.pos), token.pos)
            return BinOp("^", base, self.primary(), token.pos)
        return base

    def primary(self) -> Expr:
        t = self.tok
        if t.kind == "number":
            self.take()
            text = t.text
            is_int = text.isdigit()
            return Literal(int(text) if is_int else float(text), t.pos)
        if t.kind == "string":
            return Literal(self.string_comment(), t.pos)
        if self.at("true", "false"):
            self.take()
            return Literal(t.text == "true", t.pos)
        if self.accept("("):
            inner = self.expression()
            self.expect(")", "closing the parenthesis")
            return inner
        if self.at("{"):
            return self.array()
        if self.at("["):
            return self.matrix()
        if t.kind == "ident" or self.at("der", "initial"):
            return self.name_or_call()
        raise self.fail(f"syntax error: expected an expression, found {self.found()}")

    def name_or_call(self) -> Expr:
        if self.tok.kind == "kw":  # der(…), initial()
            first = self.take()
            name, pos = first.text, first.pos
        else:
            name, pos = self.name()
        if self.at("("):
            return self.call(name, pos)
        ref = Ref(name, pos)
        ref.subscripts = self.subscripts()
        while self.at(".") and self.peek().kind == "ident":  # a[1].b
            self.take()
            ref.name += "." + self.take().text
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
            if self.tok.kind == "ident" and self.peek().text == "=":
                key = self.take().text
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
        return Array(items, start.pos)

    def matrix(self) -> Matrix:
        start = self.expect("[")
        rows: list[list[Expr]] = [[self.expression()]]
        while self.at(",", ";"):
            if self.take().text == ";":
                rows.append([])
            rows[-1].append(self.expression())
        self.expect("]", "closing the matrix")
        return Matrix(rows, start.pos)

    def component_ref(self) -> Ref:
        if self.tok.kind != "ident":
            raise self.fail(f"syntax error: expected a connector such as 'J1.flange_a', found {self.found()}")
        expr = self.name_or_call()
        if not isinstance(expr, Ref):
            raise self.fail("syntax error: a connector, not a call, is expected in connect(…)")
        return expr


def parse_expression(text: str, source: str = "<expression>") -> Expr:
    """Parse one Modelica expression (a derived variable's binding)."""
    parser = _Parser(tokenize(text, source))
    expr = parser.expression()
    if parser.tok.kind != "eof":
        raise parser.fail(f"syntax error: unexpected {parser.found()} after the expression")
    return expr
