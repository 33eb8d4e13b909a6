//! Parsing the macro input. Entries are kept as the tokens the user wrote,
//! rendered to text for the `tableau` grammar together with a map from text
//! positions back to token spans, so the grammar is literally the one table
//! files use and every error can point at the offending token.

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream};
use syn::{Attribute, Ident, LitStr, Token, Visibility, braced, bracketed};

/// `#[attrs] vis Name { items }`.
pub struct Input {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    pub lets: Vec<Let>,
    pub fields: Vec<Field>,
}

pub struct Let {
    pub name: Ident,
    pub value: Entry,
}

pub struct Field {
    pub key: Ident,
    pub value: Value,
}

pub enum Value {
    /// `[..]` of entries.
    Vector(Vec<Entry>, Span),
    /// `[[..], [..]]`: rows with the span of each row's brackets.
    Matrix(Vec<(Vec<Entry>, Span)>, Span),
    /// `"catalogue-id"`.
    Str(LitStr),
}

impl Value {
    pub fn span(&self) -> Span {
        match self {
            Value::Vector(_, s) | Value::Matrix(_, s) => *s,
            Value::Str(l) => l.span(),
        }
    }
}

/// One expression as text, with the span of every token in it.
#[derive(Clone)]
pub struct Entry {
    pub text: String,
    pub tokens: Vec<(usize, usize, Span)>,
}

impl Entry {
    fn new(ts: TokenStream) -> Self {
        let mut e = Entry {
            text: String::new(),
            tokens: Vec::new(),
        };
        e.push_stream(ts);
        e
    }

    fn push(&mut self, s: &str, span: Span) {
        if !self.text.is_empty() {
            self.text.push(' ');
        }
        let start = self.text.len();
        self.text.push_str(s);
        self.tokens.push((start, self.text.len(), span));
    }

    fn push_stream(&mut self, ts: TokenStream) {
        for tt in ts {
            match tt {
                TokenTree::Group(g) => {
                    let (open, close) = match g.delimiter() {
                        Delimiter::Parenthesis => ("(", ")"),
                        Delimiter::Bracket => ("[", "]"),
                        Delimiter::Brace => ("{", "}"),
                        Delimiter::None => ("", ""),
                    };
                    self.push(open, g.span_open());
                    self.push_stream(g.stream());
                    self.push(close, g.span_close());
                }
                TokenTree::Ident(i) => self.push(&i.to_string(), i.span()),
                TokenTree::Punct(p) => self.push(&p.as_char().to_string(), p.span()),
                TokenTree::Literal(l) => self.push(&l.to_string(), l.span()),
            }
        }
    }

    /// The span covering text positions `pos..pos+len` (joined where the
    /// compiler allows, else the first token's).
    pub fn span_at(&self, pos: usize, len: usize) -> Span {
        let end = pos + len.max(1);
        let hit: Vec<Span> = self
            .tokens
            .iter()
            .filter(|(s, e, _)| *s < end && *e > pos)
            .map(|t| t.2)
            .collect();
        let first = hit
            .first()
            .copied()
            .or_else(|| self.tokens.last().map(|t| t.2))
            .unwrap_or_else(Span::call_site);
        hit.iter()
            .skip(1)
            .fold(first, |acc, s| acc.join(*s).unwrap_or(acc))
    }

    /// The span of the whole entry.
    pub fn span(&self) -> Span {
        self.span_at(0, self.text.len())
    }
}

impl Parse for Input {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        let name: Ident = input.parse()?;
        let body;
        braced!(body in input);
        let mut lets = Vec::new();
        let mut fields = Vec::new();
        while !body.is_empty() {
            if body.peek(Token![let]) {
                body.parse::<Token![let]>()?;
                let name: Ident = body.parse()?;
                body.parse::<Token![=]>()?;
                let mut ts = TokenStream::new();
                while !body.is_empty() && !body.peek(Token![;]) {
                    ts.extend([body.parse::<TokenTree>()?]);
                }
                if ts.is_empty() {
                    return Err(syn::Error::new(
                        name.span(),
                        format!("`let {name}` has no value"),
                    ));
                }
                body.parse::<Token![;]>()?;
                lets.push(Let {
                    name,
                    value: Entry::new(ts),
                });
                continue;
            }
            let key: Ident = body.parse()?;
            body.parse::<Token![:]>()?;
            let value = if body.peek(LitStr) {
                Value::Str(body.parse()?)
            } else {
                parse_array(&body)?
            };
            fields.push(Field { key, value });
            if !body.is_empty() {
                body.parse::<Token![,]>()?;
            }
        }
        Ok(Input {
            attrs,
            vis,
            name,
            lets,
            fields,
        })
    }
}

/// `[e, e, …]` or `[[e, …], [e, …]]`.
fn parse_array(input: ParseStream) -> syn::Result<Value> {
    let content;
    let bracket = bracketed!(content in input);
    let span = bracket.span.join();
    let items = split_commas(content.parse::<TokenStream>()?);
    let is_matrix = !items.is_empty()
        && items.iter().all(|it| {
            let v: Vec<TokenTree> = it.clone().into_iter().collect();
            matches!(v.as_slice(), [TokenTree::Group(g)] if g.delimiter() == Delimiter::Bracket)
        });
    if is_matrix {
        let rows = items
            .into_iter()
            .map(|it| {
                let Some(TokenTree::Group(g)) = it.into_iter().next() else {
                    unreachable!("checked above")
                };
                let row = split_commas(g.stream())
                    .into_iter()
                    .map(Entry::new)
                    .collect();
                (row, g.span())
            })
            .collect();
        Ok(Value::Matrix(rows, span))
    } else {
        Ok(Value::Vector(
            items.into_iter().map(Entry::new).collect(),
            span,
        ))
    }
}

/// Split a token stream at its top-level commas (a trailing comma allowed).
pub fn split_commas(ts: TokenStream) -> Vec<TokenStream> {
    let mut out = vec![TokenStream::new()];
    for tt in ts {
        match &tt {
            TokenTree::Punct(p) if p.as_char() == ',' => out.push(TokenStream::new()),
            _ => out.last_mut().unwrap().extend([tt]),
        }
    }
    if out.last().is_some_and(|t| t.is_empty()) {
        out.pop();
    }
    out
}

impl Field {
    pub fn span(&self) -> Span {
        self.key.span()
    }
}
