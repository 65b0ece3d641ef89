"""Recursive-descent parser for the Modelica subset stiction reads (see docs/modelica.md).

It parses what MSL-style models contain: ``within``, classes (several per file, nested in
packages), ``import``/``extends`` clauses, declarations with modifiers, ``connect``
equations and annotations (parsed completely, so a malformed one is a syntax error, and
kept only at class level, where ``experiment`` lives). Anything else of Modelica is refused
at its position, saying what it is and what is supported.
"""

from __future__ import annotations

from stiction.expressions.lexer import ModelicaError, Pos, tokenize
from stiction.expressions.parser import ExpressionParser
from stiction.modelica.ast import ClassDef, Connect, Declaration, Import, Modification, StoredDefinition

__all__ = ["SUPPORTED", "parse"]

SUPPORTED = (
    "supported: model/block/package classes with import and extends Modelica.Icons.* clauses, "
    "parameter and component declarations with modifiers, variables with a binding, "
    "connect equations and annotations"
)
_CLASS_KINDS = ("model", "block", "class", "package")
_UNSUPPORTED_PREFIXES = ("replaceable", "redeclare", "inner", "outer", "flow", "stream")
_TYPE_PREFIXES = ("parameter", "constant", "input", "output", "discrete")
_CLASS_STARTS = frozenset((*_CLASS_KINDS, "encapsulated", "partial"))
_SECTION_ENDS = frozenset(("end", "annotation", "public", "protected", "equation", "algorithm", "initial"))


def parse(text: str, source: str = "<modelica>") -> StoredDefinition:
    """Parse a whole ``.mo`` file; raises ModelicaError at the first problem."""
    parser = _Parser(tokenize(text, source))
    return parser.guarded(parser.stored_definition)


class _Parser(ExpressionParser):
    """The file grammar (classes, elements, modifications, connect equations) on top of the
    token cursor and expressions of ``ExpressionParser``."""

    # --- classes ----------------------------------------------------------------------
    def stored_definition(self) -> StoredDefinition:
        within = ""
        if self.accept("within"):
            if not self.at(";"):
                within = self.name("a package name after 'within'")[0]
            self.expect(";", "after the within clause")
        classes = []
        while self.kinds[self.i] != "eof":
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
            if self.kinds[self.i] == "kw" and self.at("function", "record", "connector", "type"):
                raise self.fail(f"unsupported class kind '{self.texts[self.i]}'; {SUPPORTED}")
            raise self.fail(f"syntax error: expected 'model', 'block' or 'package', found {self.found()}")
        kind = self.texts[self.take()]
        head = self.ident(f"the {kind}'s name")
        name = self.texts[head]
        if self.at("="):
            raise self.fail(f"unsupported short class definition '{kind} {name} = …'; {SUPPORTED}")
        cls = ClassDef(kind, name, self.pos(head), description=self.string_comment())
        self.composition(cls)
        end = self.expect("end", f"or a declaration in {kind} '{name}'")
        closing = self.ident(f"'{name}' after 'end'") if self.kinds[self.i] == "ident" else None
        if closing is None or self.texts[closing] != name:
            got = f"'end {self.texts[closing]}'" if closing is not None else "'end' alone"
            raise ModelicaError(
                self.pos(end if closing is None else closing),
                f"{kind} '{name}' (line {cls.pos.line}) closed by {got}",
            )
        return cls

    def composition(self, cls: ClassDef) -> None:
        texts = self.texts
        while True:
            text = texts[self.i]
            if text in ("public", "protected"):
                self.i += 1
            elif text == "equation":
                self.i += 1
                self.equations(cls)
            elif text == "initial" and self.peek() == "equation":
                raise self.fail(f"unsupported 'initial equation' section; {SUPPORTED}")
            elif text == "algorithm" or (text == "initial" and self.peek() == "algorithm"):
                raise self.fail(f"unsupported algorithm section; {SUPPORTED}")
            elif text == "annotation":
                cls.annotation.extend(self.annotation())
                self.expect(";", "after the annotation")
            elif text == "end" or self.kinds[self.i] == "eof":
                return
            else:
                self.element(cls)

    def equations(self, cls: ClassDef) -> None:
        texts, kinds, connects = self.texts, self.kinds, cls.connects
        while texts[self.i] not in _SECTION_ENDS:
            start = self.i
            if kinds[start] == "eof":
                return
            if texts[start] != "connect":
                what = texts[start] if kinds[start] == "kw" else "equation"
                raise self.fail(
                    f"unsupported {what} '{self.statement_text()}'; only connect(…) "
                    f"equations are supported ({SUPPORTED})",
                    start,
                )
            self.i += 1
            self.expect("(", "after 'connect'")
            a = self.component_ref()
            self.expect(",", "between the two connectors of connect(…)")
            b = self.component_ref()
            self.expect(")", "closing connect(…)")
            if kinds[self.i] == "string":
                self.string_comment()
            if texts[self.i] == "annotation":
                self.skip_annotation()
            self.expect(";", "after connect(…)")
            connects.append(Connect(a, b, Pos.at(self.tokens, start)))

    def statement_text(self) -> str:
        parts, j = [], self.i
        while self.kinds[j] != "eof" and self.texts[j] != ";" and len(parts) < 8:
            parts.append(self.texts[j])
            j += 1
        return " ".join(parts)

    # --- elements ---------------------------------------------------------------------
    def element(self, cls: ClassDef) -> None:
        text = self.texts[self.i]
        if text == "import":
            cls.imports.append(self.import_clause())
        elif text == "extends":
            self.i += 1
            cls.extends.append(self.name("a class name after 'extends'"))
            if self.at("("):
                self.class_modification()
            if self.at("annotation"):
                self.skip_annotation()
        elif text in _CLASS_STARTS:
            cls.classes.append(self.class_definition())
        else:
            self.accept("final")
            if self.at(*_UNSUPPORTED_PREFIXES):
                raise self.fail(f"unsupported '{self.texts[self.i]}' element; {SUPPORTED}")
            cls.declarations.extend(self.component_clause())
        self.expect(";", "after the declaration")

    def import_clause(self) -> Import:
        start = self.pos(self.take())
        if self.kinds[self.i] == "ident" and self.peek() == "=":
            alias = self.texts[self.take()]
            self.take()
            target, _ = self.name("a class name")
            return Import(alias, target, False, start)
        target, _ = self.name("a class name after 'import'")
        if self.accept(".*"):  # the lexer reads ".*" as one (element-wise) operator
            return Import(None, target, True, start)
        if self.accept("."):
            if self.accept("*"):
                return Import(None, target, True, start)
            raise self.fail(
                "unsupported import form; use 'import A.B;', 'import X = A.B;' or 'import A.B.*;'"
            )
        return Import(None, target, False, start)

    def component_clause(self) -> list[Declaration]:
        prefix = ""
        while self.texts[self.i] in _TYPE_PREFIXES:  # `parameter input Real k`: the first counts
            prefix = prefix or self.texts[self.i]
            self.i += 1
        type_name, type_pos = self.name("a type or class name")
        if self.texts[self.i] == "[":
            raise self.fail(f"unsupported array type '{type_name}[…]'; {SUPPORTED}")
        decls = [self.declaration(type_name, type_pos, prefix)]
        while self.accept(","):
            decls.append(self.declaration(type_name, type_pos, prefix))
        return decls

    def declaration(self, type_name: str, type_pos: Pos, prefix: str) -> Declaration:
        head = self.ident("a component name")
        texts, name = self.texts, self.texts[head]
        if texts[self.i] == "[":
            raise self.fail(f"unsupported array component '{name}[…]'; {SUPPORTED}")
        decl = Declaration(type_name, type_pos, name, Pos.at(self.tokens, head), prefix)
        if texts[self.i] == "(":
            decl.args = self.class_modification()
        if texts[self.i] in ("=", ":="):
            self.i += 1
            decl.binding = self.expression()
        if texts[self.i] == "if":
            raise self.fail(f"unsupported conditional component '{name} if …'; {SUPPORTED}")
        if self.kinds[self.i] == "string":
            decl.description = self.string_comment()
        if texts[self.i] == "annotation":
            self.skip_annotation()
        return decl

    # --- modifications ----------------------------------------------------------------
    def class_modification(self) -> list[Modification]:
        self.expect("(")
        args: list[Modification] = []
        if self.texts[self.i] != ")":
            args.append(self.argument())
            while self.texts[self.i] == ",":
                self.i += 1
                args.append(self.argument())
        self.expect(")", "closing the modifier list")
        return args

    def argument(self) -> Modification:
        texts = self.texts
        while texts[self.i] in ("each", "final"):
            self.i += 1
        i = self.i
        if texts[i] in ("redeclare", "replaceable"):
            raise self.fail(f"unsupported '{texts[i]}' modifier; {SUPPORTED}")
        if self.kinds[i] == "ident" and texts[i + 1] != ".":  # the common case, as name() reads it
            self.i = i + 1
            name, pos = texts[i], Pos.at(self.tokens, i)
        else:
            name, pos = self.name("a modifier name")
        mod = Modification(name, pos)
        text = texts[self.i]
        if text == "(":
            mod.args = self.class_modification()
            text = texts[self.i]
        if text in ("=", ":="):
            self.i += 1
            mod.value = self.expression()
        if self.kinds[self.i] == "string":
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
        kinds, texts, i = self.kinds, self.texts, self.i
        while stack:
            kind, text = kinds[i], texts[i]
            if kind == "op":
                if text in closers:
                    stack.append(closers[text])
                elif text in (")", "]", "}") and text != stack.pop():
                    self.i = i
                    raise self.fail(f"syntax error: unbalanced '{text}' in the annotation")
            elif kind == "eof":
                raise ModelicaError(self.pos(opening), "syntax error: the annotation's '(' is never closed")
            i += 1
        self.i = i
