//! Derived variables (`[variables]`, `slip = "J1.w - J2.w"`): the Modelica expression each is
//! written as, parsed when the model is read. The grammar is Modelica's, as the Python parser
//! reads it (`stiction/expressions/parser.py`): numbers, `true`/`false`, dotted names,
//! `+ - * / ^` (and the element-wise `.+ .- .* ./ .^`), relations, `and`/`or`/`not`,
//! `if … then … elseif … else …` and calls of the functions in `FUNCTIONS` and `der`. What a
//! scalar over result rows cannot be (strings, arrays, subscripts, named arguments) is refused
//! with the construct named. Names are resolved against the model's variables when a system is
//! built (`system::formula`).

use crate::error::{ModelError, ModelResult};

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Lt,
    Le,
    Gt,
    Ge,
    Eq,
    Ne,
    And,
    Or,
}

/// A parsed expression; names are still text.
#[derive(Debug, Clone, PartialEq)]
pub enum Expr {
    Num(f64),
    Name(String),
    Neg(Box<Expr>),
    Not(Box<Expr>),
    Bin(BinOp, Box<Expr>, Box<Expr>),
    If(Box<Expr>, Box<Expr>, Box<Expr>),
    /// A function of `FUNCTIONS` (by its short name) and its arguments.
    Call(&'static str, Vec<Expr>),
    /// `der(name)`.
    Der(String),
}

/// The functions an expression may call, with their number of arguments: those of the Python
/// evaluator (`stiction/expressions/evaluate.py`), each also as `Modelica.Math.<name>`.
pub const FUNCTIONS: &[(&str, usize)] = &[
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("asin", 1),
    ("acos", 1),
    ("atan", 1),
    ("atan2", 2),
    ("sinh", 1),
    ("cosh", 1),
    ("tanh", 1),
    ("exp", 1),
    ("log", 1),
    ("log10", 1),
    ("sqrt", 1),
    ("abs", 1),
    ("sign", 1),
    ("floor", 1),
    ("ceil", 1),
    ("max", 2),
    ("min", 2),
    ("from_rpm", 1),
    ("to_rpm", 1),
    ("from_degC", 1),
    ("to_degC", 1),
    ("from_deg", 1),
    ("to_deg", 1),
];

/// Modelica's constants by name.
pub const CONSTANTS: &[(&str, f64)] = &[
    ("Modelica.Constants.pi", std::f64::consts::PI),
    ("Modelica.Constants.e", std::f64::consts::E),
    ("Modelica.Constants.g_n", 9.80665),
    ("Modelica.Constants.eps", f64::EPSILON),
    ("Modelica.Constants.small", 1e-60),
    ("Modelica.Constants.T_zero", -273.15),
];

/// The unit conversions, only by their full name (as the Python evaluator has them).
const CONVERSIONS: &str = "Modelica.Units.Conversions.";

/// One derived variable as the model file writes it, parsed.
#[derive(Debug, Clone, PartialEq)]
pub struct DerivedSpec {
    pub name: String,
    pub text: String,
    pub expr: Expr,
}

impl DerivedSpec {
    /// Parses `name = "text"`; a syntax error or a construct that is no scalar names both.
    pub fn parse(name: &str, text: &str) -> ModelResult<Self> {
        let expr = Parser::new(text)
            .and_then(|mut p| p.whole())
            .map_err(|why| ModelError::File(format!("variable '{name}' = \"{text}\": {why}")))?;
        Ok(Self {
            name: name.to_string(),
            text: text.to_string(),
            expr,
        })
    }
}

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Num(f64),
    Ident(String),
    Op(&'static str),
    Str,
    End,
}

const OPERATORS: &[&str] = &[
    ".+", ".-", ".*", "./", ".^", "<=", ">=", "==", "<>", "+", "-", "*", "/", "^", "<", ">", "(",
    ")", ",", "=", "[", "]", "{", "}", ".", ":", ";",
];

fn tokenize(text: &str) -> Result<Vec<Tok>, String> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c.is_ascii_digit() || (c == b'.' && b.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            let start = i;
            while i < b.len() && (b[i].is_ascii_digit() || b[i] == b'.') {
                i += 1;
            }
            if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
                let sign = usize::from(matches!(b.get(i + 1), Some(b'+' | b'-')));
                if b.get(i + 1 + sign).is_some_and(u8::is_ascii_digit) {
                    i += 1 + sign;
                    while i < b.len() && b[i].is_ascii_digit() {
                        i += 1;
                    }
                }
            }
            let number = &text[start..i];
            let value = number
                .parse::<f64>()
                .map_err(|_| format!("'{number}' is not a number"))?;
            out.push(Tok::Num(value));
        } else if c.is_ascii_alphabetic() || c == b'_' {
            let start = i;
            while i < b.len() && (b[i].is_ascii_alphanumeric() || b[i] == b'_') {
                i += 1;
            }
            out.push(Tok::Ident(text[start..i].to_string()));
        } else if c == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += if b[i] == b'\\' { 2 } else { 1 };
            }
            i += 1;
            out.push(Tok::Str);
        } else if let Some(op) = OPERATORS.iter().find(|op| text[i..].starts_with(**op)) {
            i += op.len();
            out.push(Tok::Op(op));
        } else {
            let ch = text[i..].chars().next().unwrap_or('?');
            return Err(format!("syntax error: unexpected '{ch}'"));
        }
    }
    out.push(Tok::End);
    Ok(out)
}

/// Nesting deeper than this is refused (as the Python parser does) rather than overflowing.
const MAX_DEPTH: usize = 200;

struct Parser {
    toks: Vec<Tok>,
    i: usize,
    depth: usize,
}

fn is_word(t: &Tok, word: &str) -> bool {
    matches!(t, Tok::Ident(s) if s == word)
}

fn describe(t: &Tok) -> String {
    match t {
        Tok::Num(v) => format!("'{v}'"),
        Tok::Ident(s) => format!("'{s}'"),
        Tok::Op(op) => format!("'{op}'"),
        Tok::Str => "a string".into(),
        Tok::End => "the end".into(),
    }
}

impl Parser {
    fn new(text: &str) -> Result<Self, String> {
        Ok(Parser {
            toks: tokenize(text)?,
            i: 0,
            depth: 0,
        })
    }

    fn peek(&self) -> &Tok {
        &self.toks[self.i]
    }

    fn op(&self, op: &str) -> bool {
        matches!(self.peek(), Tok::Op(o) if *o == op)
    }

    fn word(&self, word: &str) -> bool {
        is_word(self.peek(), word)
    }

    fn next(&mut self) -> Tok {
        let t = self.toks[self.i].clone();
        if t != Tok::End {
            self.i += 1;
        }
        t
    }

    fn expect_word(&mut self, word: &str, context: &str) -> Result<(), String> {
        if !self.word(word) {
            return Err(format!(
                "syntax error: expected '{word}' {context}, found {}",
                describe(self.peek())
            ));
        }
        self.i += 1;
        Ok(())
    }

    fn expect_op(&mut self, op: &str, context: &str) -> Result<(), String> {
        if !self.op(op) {
            return Err(format!(
                "syntax error: expected '{op}' {context}, found {}",
                describe(self.peek())
            ));
        }
        self.i += 1;
        Ok(())
    }

    fn whole(&mut self) -> Result<Expr, String> {
        let e = self.expression()?;
        if *self.peek() != Tok::End {
            return Err(format!(
                "syntax error: unexpected {} after the expression",
                describe(self.peek())
            ));
        }
        Ok(e)
    }

    fn expression(&mut self) -> Result<Expr, String> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(format!("expression deeper than {MAX_DEPTH} levels"));
        }
        let e = if self.word("if") {
            self.i += 1;
            self.if_rest()?
        } else {
            self.logical(true)?
        };
        self.depth -= 1;
        Ok(e)
    }

    /// After `if` (or `elseif`): `cond then a (elseif …)* else b`.
    fn if_rest(&mut self) -> Result<Expr, String> {
        let cond = self.expression()?;
        self.expect_word("then", "in the if-expression")?;
        let then = self.expression()?;
        let other = if self.word("elseif") {
            self.i += 1;
            self.if_rest()?
        } else {
            self.expect_word("else", "in the if-expression")?;
            self.expression()?
        };
        Ok(Expr::If(Box::new(cond), Box::new(then), Box::new(other)))
    }

    fn logical(&mut self, or: bool) -> Result<Expr, String> {
        let (word, op) = if or {
            ("or", BinOp::Or)
        } else {
            ("and", BinOp::And)
        };
        let sub = |p: &mut Self| if or { p.logical(false) } else { p.negation() };
        let mut left = sub(self)?;
        while self.word(word) {
            self.i += 1;
            left = Expr::Bin(op, Box::new(left), Box::new(sub(self)?));
        }
        Ok(left)
    }

    fn negation(&mut self) -> Result<Expr, String> {
        if self.word("not") {
            self.i += 1;
            return Ok(Expr::Not(Box::new(self.relation()?)));
        }
        self.relation()
    }

    fn relation(&mut self) -> Result<Expr, String> {
        let left = self.arithmetic()?;
        let op = match self.peek() {
            Tok::Op("<") => BinOp::Lt,
            Tok::Op("<=") => BinOp::Le,
            Tok::Op(">") => BinOp::Gt,
            Tok::Op(">=") => BinOp::Ge,
            Tok::Op("==") => BinOp::Eq,
            Tok::Op("<>") => BinOp::Ne,
            _ => return Ok(left),
        };
        self.i += 1;
        Ok(Expr::Bin(op, Box::new(left), Box::new(self.arithmetic()?)))
    }

    fn arithmetic(&mut self) -> Result<Expr, String> {
        let mut left = match self.peek() {
            Tok::Op("-") => {
                self.i += 1;
                Expr::Neg(Box::new(self.term()?))
            }
            Tok::Op("+") => {
                self.i += 1;
                self.term()?
            }
            _ => self.term()?,
        };
        loop {
            let op = match self.peek() {
                Tok::Op("+" | ".+") => BinOp::Add,
                Tok::Op("-" | ".-") => BinOp::Sub,
                _ => return Ok(left),
            };
            self.i += 1;
            left = Expr::Bin(op, Box::new(left), Box::new(self.term()?));
        }
    }

    fn term(&mut self) -> Result<Expr, String> {
        let mut left = self.factor()?;
        loop {
            let op = match self.peek() {
                Tok::Op("*" | ".*") => BinOp::Mul,
                Tok::Op("/" | "./") => BinOp::Div,
                _ => return Ok(left),
            };
            self.i += 1;
            left = Expr::Bin(op, Box::new(left), Box::new(self.factor()?));
        }
    }

    fn factor(&mut self) -> Result<Expr, String> {
        let base = self.primary()?;
        if !(self.op("^") || self.op(".^")) {
            return Ok(base);
        }
        self.i += 1;
        // 2^-1 is not Modelica, but a unary sign here is harmless (as the Python parser has it)
        let exponent = match self.peek() {
            Tok::Op("-") => {
                self.i += 1;
                Expr::Neg(Box::new(self.primary()?))
            }
            Tok::Op("+") => {
                self.i += 1;
                self.primary()?
            }
            _ => self.primary()?,
        };
        Ok(Expr::Bin(BinOp::Pow, Box::new(base), Box::new(exponent)))
    }

    fn primary(&mut self) -> Result<Expr, String> {
        match self.next() {
            Tok::Num(v) => Ok(Expr::Num(v)),
            Tok::Ident(w) if w == "true" => Ok(Expr::Num(1.0)),
            Tok::Ident(w) if w == "false" => Ok(Expr::Num(0.0)),
            Tok::Op("(") => {
                let inner = self.expression()?;
                self.expect_op(")", "closing the parenthesis")?;
                Ok(inner)
            }
            Tok::Str => Err("a string is not a number: a derived variable is a Real".into()),
            Tok::Op("{" | "[") => {
                Err("array-valued variables are not supported (an array or matrix)".into())
            }
            Tok::Ident(first) if !is_keyword(&first) => self.name_or_call(first),
            t => Err(format!(
                "syntax error: expected an expression, found {}",
                describe(&t)
            )),
        }
    }

    fn name_or_call(&mut self, first: String) -> Result<Expr, String> {
        let mut name = first;
        while self.op(".") && matches!(self.toks[self.i + 1], Tok::Ident(_)) {
            if let Tok::Ident(part) = &self.toks[self.i + 1] {
                name = format!("{name}.{part}");
            }
            self.i += 2;
        }
        if self.op("[") {
            return Err(format!(
                "subscripts ('{name}[…]') are not supported: a derived variable is a scalar"
            ));
        }
        if !self.op("(") {
            return Ok(Expr::Name(name));
        }
        self.i += 1;
        let mut args = Vec::new();
        while !self.op(")") {
            if matches!(self.peek(), Tok::Ident(_)) && self.toks[self.i + 1] == Tok::Op("=") {
                return Err(format!(
                    "named arguments in a call of '{name}' are not supported"
                ));
            }
            args.push(self.expression()?);
            if !self.op(",") {
                break;
            }
            self.i += 1;
        }
        self.expect_op(")", &format!("closing the call of '{name}'"))?;
        call(&name, args)
    }
}

fn is_keyword(word: &str) -> bool {
    matches!(
        word,
        "and" | "or" | "not" | "if" | "then" | "else" | "elseif" | "end"
    )
}

fn is_conversion(name: &str) -> bool {
    name.contains("rpm") || name.contains("deg")
}

/// The function `func` names: `sin` or `Modelica.Math.sin`; a unit conversion only by its full
/// name, `Modelica.Units.Conversions.to_rpm` (as the Python evaluator knows them).
fn function(func: &str) -> Option<&'static (&'static str, usize)> {
    let short = match func.strip_prefix(CONVERSIONS) {
        Some(s) => is_conversion(s).then_some(s)?,
        None => {
            let s = func.strip_prefix("Modelica.Math.").unwrap_or(func);
            (!is_conversion(s)).then_some(s)?
        }
    };
    FUNCTIONS.iter().find(|(n, _)| *n == short)
}

/// A call of `func` checked: `der` of a name, or a known function with its number of arguments.
fn call(func: &str, mut args: Vec<Expr>) -> Result<Expr, String> {
    if func == "der" {
        return match args.as_slice() {
            [Expr::Name(name)] => Ok(Expr::Der(name.clone())),
            _ => Err("der(…) takes one variable, der(J.phi)".into()),
        };
    }
    let Some(&(name, arity)) = function(func) else {
        let known: Vec<&str> = (FUNCTIONS.iter())
            .map(|(n, _)| *n)
            .filter(|n| !is_conversion(n))
            .collect();
        return Err(format!(
            "unknown function '{func}' (supported: {}, der, {CONVERSIONS}from_rpm/to_rpm/from_degC/to_degC/from_deg/to_deg)",
            known.join(", ")
        ));
    };
    if args.len() != arity {
        return Err(format!(
            "{func}(…) takes {arity} argument{}, got {}",
            if arity == 1 { "" } else { "s" },
            args.len()
        ));
    }
    args.shrink_to_fit();
    Ok(Expr::Call(name, args))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Expr, String> {
        DerivedSpec::parse("v", text)
            .map(|d| d.expr)
            .map_err(|e| e.to_string())
    }

    fn name(s: &str) -> Box<Expr> {
        Box::new(Expr::Name(s.into()))
    }

    #[test]
    fn expressions_parse_with_modelica_precedence() {
        assert_eq!(
            parse("J1.w - J2.w").unwrap(),
            Expr::Bin(BinOp::Sub, name("J1.w"), name("J2.w"))
        );
        // -a^2 is -(a^2); a*b+c is (a*b)+c
        assert_eq!(
            parse("-x^2").unwrap(),
            Expr::Neg(Box::new(Expr::Bin(
                BinOp::Pow,
                name("x"),
                Box::new(Expr::Num(2.0))
            )))
        );
        assert!(matches!(
            parse("a*b + c").unwrap(),
            Expr::Bin(BinOp::Add, ..)
        ));
        assert!(matches!(
            parse("if a > 1 then 1 elseif a < 0 then 2 else 3").unwrap(),
            Expr::If(_, _, other) if matches!(*other, Expr::If(..))
        ));
        assert_eq!(
            parse("Modelica.Math.abs(der(J.phi))").unwrap(),
            Expr::Call("abs", vec![Expr::Der("J.phi".into())])
        );
        assert_eq!(
            parse("Modelica.Units.Conversions.to_rpm(J.w)").unwrap(),
            Expr::Call("to_rpm", vec![Expr::Name("J.w".into())])
        );
        assert_eq!(parse("1.5e-3").unwrap(), Expr::Num(1.5e-3));
        assert!(matches!(
            parse("not a > 1 and b").unwrap(),
            Expr::Bin(BinOp::And, ..)
        ));
    }

    #[test]
    fn what_is_no_scalar_is_refused_by_name() {
        let err = |text: &str| parse(text).unwrap_err();
        assert!(err("\"text\"").contains("string"), "{}", err("\"text\""));
        assert!(err("{1, 2}").contains("array"));
        assert!(err("brake.mu_pos[1, 2]").contains("subscripts"));
        assert!(err("median(J.w)").contains("unknown function 'median'"));
        assert!(err("max(J.w)").contains("takes 2 arguments"));
        assert!(err("der(J.w + 1)").contains("der(…) takes one variable"));
        assert!(err("sin(x=1)").contains("named arguments"));
        assert!(err("J.w +").contains("syntax error"));
        assert!(err("to_rpm(J.w)").contains("unknown function 'to_rpm'"));
        assert!(err("J.w J.phi").contains("after the expression"));
        assert!(err(&"(".repeat(500)).contains("deeper"));
        assert!(err("J.w +").starts_with("variable 'v' = \"J.w +\": "));
    }
}
