"""Recursive-descent parser for the Modelica subset stiction reads (see docs/modelica.md).

It parses what MSL-style models contain: ``within``, classes (several per file, nested in
packages), ``import``/``extends`` clauses, declarations with modifiers, ``connect``
equations and annotations (parsed completely, so a malformed one is a syntax error, and
kept only at class level, where ``experiment`` lives). Anything else of Modelica is refused
at its position, saying what it is and what is supported.

A construct refused but readable (another equation, a ``when`` block, an algorithm section, a
conditional, replaceable or array component, a function) is reported and read past, so one
run reports them all (``StoredDefinition.refused``; a refused declaration stays in the tree,
marked, so nothing that uses it is reported again). A syntax error stops the reading: it is
reported after those found before it.
"""

from __future__ import annotations

from typing import Any

from stiction.expressions.lexer import ModelicaError, Pos, Tokens, tokenize
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
_BLOCKS = frozenset(("when", "if", "for", "while"))  # equations and statements up to `end when;` …
_OPENING = {"(": 1, "[": 1, "{": 1, ")": -1, "]": -1, "}": -1}


class _Lost(Exception):
    """Reading past a refused construct found no end to it: stop with what was reported."""


def parse(text: str, source: str = "<modelica>") -> StoredDefinition:
    """Parse a whole ``.mo`` file. Refused constructs are collected in ``refused``; a syntax
    error raises ModelicaError listing them and it."""
    parser = _Parser(tokenize(text, source))
    try:
        tree = parser.guarded(parser.stored_definition)
    except ModelicaError as exc:
        raise ModelicaError.of([*parser.refused, exc]) from None
    except _Lost:
        raise ModelicaError.of(parser.refused) from None
    tree.refused = parser.refused
    return tree


class _Parser(ExpressionParser):
    """The file grammar (classes, elements, modifications, connect equations) on top of the
    token cursor and expressions of ``ExpressionParser``."""

    def __init__(self, tokens: Tokens) -> None:
        super().__init__(tokens)
        self.refused: list[ModelicaError] = []

    def refuse(self, message: str, i: int | None = None) -> None:
        """Report a construct the parser reads past."""
        self.refused.append(self.fail(message, i))

    def skip_to(self, i: int, stop: frozenset[str]) -> int:
        """The index of the first token of ``stop`` from ``i`` outside brackets (eof: _Lost)."""
        texts, kinds, depth = self.texts, self.kinds, 0
        while True:
            text = texts[i]
            if kinds[i] == "eof":
                raise _Lost
            if depth == 0 and text in stop:
                return i
            if kinds[i] == "op":
                depth = max(0, depth + _OPENING.get(text, 0))
            i += 1

    def skip_statement(self) -> None:
        """Past the equation or statement at the cursor and its ';': a `when`, `if`, `for` or
        `while` block to its `end when;` (nested blocks too), anything else to its ';'."""
        texts, i, blocks = self.texts, self.i, 0
        while True:
            if texts[i] in _BLOCKS:  # at the start of a statement: a block opens
                blocks += 1
            i = self.skip_to(i, frozenset((";", "then", "loop", "end")))
            text = texts[i]
            i += 1
            if text == "end" and texts[i] in _BLOCKS:
                blocks -= 1
                i += 1
            elif text == "end":
                raise _Lost
            if text == ";" and blocks == 0:
                self.i = i
                return

    def skip_section(self) -> None:
        """Past the statements of a refused section (`algorithm`, `initial equation`)."""
        self.i += 2 if self.texts[self.i] == "initial" else 1
        while self.texts[self.i] not in _SECTION_ENDS:
            if self.kinds[self.i] == "eof":
                return
            self.skip_statement()

    # --- classes ----------------------------------------------------------------------
    def stored_definition(self) -> StoredDefinition:
        within = ""
        if self.accept("within"):
            if not self.at(";"):
                within = self.name("a package name after 'within'")[0]
            self.expect(";", "after the within clause")
        classes: list[ClassDef] = []
        while self.kinds[self.i] != "eof":
            self.accept("final")
            cls = self.class_definition()
            if cls is not None:
                classes.append(cls)
            self.expect(";", f"after 'end {cls.name}'" if cls else "after the class")
        if not classes and self.refused:
            raise _Lost  # only refused classes: those errors are the answer
        if not classes:
            raise self.fail("no model in the text: expected 'model Name … end Name;'")
        return StoredDefinition(within, classes)

    def class_definition(self) -> ClassDef | None:
        """A class, or None for one refused and read past (up to its closing ';')."""
        self.accept("encapsulated")
        self.accept("partial")
        if not self.at(*_CLASS_KINDS):
            if self.kinds[self.i] == "kw" and self.at("function", "record", "connector", "type"):
                self.refuse(f"unsupported class kind '{self.texts[self.i]}'; {SUPPORTED}")
                self.i += 1
                self.skip_class(self.texts[self.ident("the class's name")])
                return None
            raise self.fail(f"syntax error: expected 'model', 'block' or 'package', found {self.found()}")
        kind = self.texts[self.take()]
        head = self.ident(f"the {kind}'s name")
        name = self.texts[head]
        if self.at("="):
            self.refuse(f"unsupported short class definition '{kind} {name} = …'; {SUPPORTED}")
            self.skip_class(name)
            return None
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

    def skip_class(self, name: str) -> None:
        """Past a refused class up to its closing ';': a short one (`type T = Real;`) or a
        long one to its `end name`."""
        if self.at("="):
            self.i = self.skip_to(self.i, frozenset((";",)))
            return
        texts, i = self.texts, self.i
        while True:
            i = self.skip_to(i, frozenset(("end",))) + 1
            if texts[i] == name:
                self.i = i + 1
                return

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
                self.refuse(f"unsupported 'initial equation' section; {SUPPORTED}")
                self.skip_section()
            elif text == "algorithm" or (text == "initial" and self.peek() == "algorithm"):
                self.refuse(f"unsupported algorithm section; {SUPPORTED}")
                self.skip_section()
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
                self.refuse(
                    f"unsupported {what} '{self.statement_text()}'; only connect(…) "
                    f"equations are supported ({SUPPORTED})",
                    start,
                )
                self.skip_statement()
                continue
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
            cls.extends_args.append(self.class_modification() if self.at("(") else [])
            if self.at("annotation"):
                self.skip_annotation()
        elif text in _CLASS_STARTS:
            inner = self.class_definition()
            if inner is not None:
                cls.classes.append(inner)
        else:
            self.accept("final")
            if self.at(*_UNSUPPORTED_PREFIXES):
                self.refuse(f"unsupported '{self.texts[self.i]}' element; {SUPPORTED}")
                while self.at(*_UNSUPPORTED_PREFIXES, "final"):
                    self.i += 1
                if self.at(*_CLASS_STARTS):  # `replaceable model M = …`, `redeclare model …`
                    self.class_definition()
                else:
                    decls = self.component_clause()
                    for decl in decls:
                        decl.refused = True
                    cls.declarations.extend(decls)
                    if self.accept("constrainedby"):
                        self.name("a class name after 'constrainedby'")
                        if self.at("("):
                            self.class_modification()
            else:
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
            self.refuse("unsupported import form; use 'import A.B;', 'import X = A.B;' or 'import A.B.*;'")
            self.i = self.skip_to(self.i, frozenset((";",)))
        return Import(None, target, False, start)

    def component_clause(self) -> list[Declaration]:
        prefix = ""
        while self.texts[self.i] in _TYPE_PREFIXES:  # `parameter input Real k`: the first counts
            prefix = prefix or self.texts[self.i]
            self.i += 1
        type_name, type_pos = self.name("a type or class name")
        array = self.texts[self.i] == "["
        if array:
            self.refuse(f"unsupported array type '{type_name}[…]'; {SUPPORTED}")
            self.skip_subscripts()
        decls = [self.declaration(type_name, type_pos, prefix)]
        while self.accept(","):
            decls.append(self.declaration(type_name, type_pos, prefix))
        if array:
            for decl in decls:
                decl.refused = True
        return decls

    def skip_subscripts(self) -> None:
        """Past a refused array dimension `[…]`."""
        self.i = self.skip_to(self.i + 1, frozenset(("]",))) + 1

    def declaration(self, type_name: str, type_pos: Pos, prefix: str) -> Declaration:
        head = self.ident("a component name")
        texts, name = self.texts, self.texts[head]
        decl = Declaration(type_name, type_pos, name, Pos.at(self.tokens, head), prefix)
        if texts[self.i] == "[":
            self.refuse(f"unsupported array component '{name}[…]'; {SUPPORTED}")
            self.skip_subscripts()
            decl.refused = True
        if texts[self.i] == "(":
            decl.args = self.class_modification()
        if texts[self.i] in ("=", ":="):
            self.i += 1
            decl.binding = self.expression()
        if texts[self.i] == "if":
            self.refuse(f"unsupported conditional component '{name} if …'; {SUPPORTED}")
            self.i += 1
            self.expression()
            decl.refused = True
        if self.kinds[self.i] == "string":
            decl.description = self.string_comment()
        if texts[self.i] == "annotation":
            if self.own_annotation():
                decl.annotation = self.annotation()
            else:
                self.skip_annotation()
        return decl

    def own_annotation(self) -> bool:
        """Whether the annotation ahead carries one of stiction's own entries at its top
        (``annotation(__stiction_wear(…))``, as the exporter writes it): then it is parsed."""
        return self.texts[self.i + 1] == "(" and self.texts[self.i + 2].startswith("__stiction_")

    # --- modifications ----------------------------------------------------------------
    def class_modification(self) -> list[Modification]:
        self.expect("(")
        args: list[Any] = []  # None for a refused modifier
        refused = len(self.refused)
        if self.texts[self.i] != ")":
            args.append(self.argument())
            while self.texts[self.i] == ",":
                self.i += 1
                args.append(self.argument())
        self.expect(")", "closing the modifier list")
        return args if len(self.refused) == refused else [a for a in args if a is not None]

    def argument(self) -> Modification | None:
        """One modifier, or None for a refused one (read past)."""
        texts = self.texts
        while texts[self.i] in ("each", "final"):
            self.i += 1
        i = self.i
        if texts[i] in ("redeclare", "replaceable"):
            self.refuse(f"unsupported '{texts[i]}' modifier; {SUPPORTED}")
            self.i = self.skip_to(i, frozenset((",", ")")))
            return None
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
