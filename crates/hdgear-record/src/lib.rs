//! `#[derive(Record)]`: a table row's column names, derived from the struct serde writes.
//!
//! A row of an hdgear table (a sweep's, a branch's, a trajectory's) is a `Serialize` struct;
//! its CSV header is what serde writes for it: each field's name (or its `#[serde(rename)]`), in
//! field order, and a nested record's own columns in its place (csv writes a nested struct's
//! fields inline). The derive reads the same struct and writes `hdgear::output::Record`'s
//! `COLUMNS` from it, at compile time, so that a table with no rows still has its header and
//! no column list is kept by hand beside the fields.
//!
//! - `#[record(nested)]` on a field: its type is a record whose columns stand in its place.
//! - A type parameter takes its default (`SweepRow<V = Params>` is `SweepRow<Params>`'s record):
//!   the columns are a constant, and a generic row's columns are its default's.
//! - Serde attributes that make a row's columns other than its fields (`flatten`,
//!   `skip_serializing_if`, `rename_all`, `rename(serialize = …)`) are refused with a compile error,
//!   not guessed at.

use proc_macro::TokenStream;
use proc_macro2::TokenStream as Tokens;
use quote::quote;
use syn::{Data, DeriveInput, Fields, GenericParam, LitStr, Type, parse_macro_input};

/// Implements `hdgear::output::Record` for a struct with named fields (see the crate's doc).
#[proc_macro_derive(Record, attributes(record))]
pub fn derive_record(input: TokenStream) -> TokenStream {
    let input = parse_macro_input!(input as DeriveInput);
    expand(&input)
        .unwrap_or_else(syn::Error::into_compile_error)
        .into()
}

/// One field's place in the columns: a name, or a nested record's type.
enum Part {
    Name(String),
    Nested(Type),
}

fn expand(input: &DeriveInput) -> syn::Result<Tokens> {
    let Data::Struct(data) = &input.data else {
        return Err(syn::Error::new_spanned(input, "a record is a struct"));
    };
    let Fields::Named(fields) = &data.fields else {
        return Err(syn::Error::new_spanned(input, "a record has named fields"));
    };
    for attr in input.attrs.iter().filter(|a| a.path().is_ident("serde")) {
        attr.parse_nested_meta(|m| {
            Err(m.error("a record's columns are its fields: no container serde attribute"))
        })?;
    }
    let (args, defaults) = type_arguments(input)?;
    let mut parts = Vec::new();
    for field in &fields.named {
        let ident = field.ident.as_ref().expect("named fields have names");
        let (mut rename, mut skip) = (None, false);
        for attr in field.attrs.iter().filter(|a| a.path().is_ident("serde")) {
            attr.parse_nested_meta(|m| {
                if m.path.is_ident("rename") {
                    let lit: LitStr = m.value()?.parse()?;
                    rename = Some(lit.value());
                    Ok(())
                } else if m.path.is_ident("skip") || m.path.is_ident("skip_serializing") {
                    skip = true;
                    Ok(())
                } else if m.path.is_ident("default") || m.path.is_ident("alias") {
                    // reading only: the columns written are the same
                    if m.input.peek(syn::Token![=]) {
                        let _: LitStr = m.value()?.parse()?;
                    }
                    Ok(())
                } else {
                    Err(m.error("this serde attribute is not read by #[derive(Record)]"))
                }
            })?;
        }
        let mut nested = false;
        for attr in field.attrs.iter().filter(|a| a.path().is_ident("record")) {
            attr.parse_nested_meta(|m| {
                if m.path.is_ident("nested") {
                    nested = true;
                    Ok(())
                } else {
                    Err(m.error("#[record(…)] takes `nested`"))
                }
            })?;
        }
        if skip {
            continue;
        }
        parts.push(if nested {
            Part::Nested(with_defaults(&field.ty, &defaults))
        } else {
            Part::Name(rename.unwrap_or_else(|| ident.to_string().trim_start_matches("r#").into()))
        });
    }
    let name = &input.ident;
    let parts = runs(parts);
    Ok(quote! {
        impl ::hdgear::output::Record for #name #args {
            const COLUMNS: &'static [&'static str] = {
                const PARTS: &[&[&str]] = &[#(#parts),*];
                const COLUMNS: [&str; ::hdgear::output::column_count(PARTS)] =
                    ::hdgear::output::join_columns(PARTS);
                &COLUMNS
            };
        }
    })
}

/// The type's arguments in the impl (`'_` for a lifetime, the default for a type parameter) and
/// each type parameter's default, by name.
fn type_arguments(input: &DeriveInput) -> syn::Result<(Tokens, Vec<(syn::Ident, Type)>)> {
    let mut args = Vec::new();
    let mut defaults = Vec::new();
    for p in &input.generics.params {
        match p {
            GenericParam::Lifetime(_) => args.push(quote!('_)),
            GenericParam::Type(t) => {
                let Some(d) = &t.default else {
                    return Err(syn::Error::new_spanned(
                        t,
                        "a record's type parameter needs a default: its columns are the default's",
                    ));
                };
                args.push(quote!(#d));
                defaults.push((t.ident.clone(), d.clone()));
            }
            GenericParam::Const(c) => {
                return Err(syn::Error::new_spanned(
                    c,
                    "a record has no const parameter",
                ));
            }
        }
    }
    Ok((
        if args.is_empty() {
            quote!()
        } else {
            quote!(<#(#args),*>)
        },
        defaults,
    ))
}

/// `ty`, or its default when it is one of the type parameters.
fn with_defaults(ty: &Type, defaults: &[(syn::Ident, Type)]) -> Type {
    if let Type::Path(p) = ty
        && p.qself.is_none()
        && let Some(ident) = p.path.get_ident()
        && let Some((_, d)) = defaults.iter().find(|(i, _)| i == ident)
    {
        return d.clone();
    }
    ty.clone()
}

/// The parts as constant slices: each run of plain names one slice literal, each nested
/// record its own `COLUMNS`.
fn runs(parts: Vec<Part>) -> Vec<Tokens> {
    let mut out = Vec::new();
    let mut names: Vec<String> = Vec::new();
    for part in parts {
        match part {
            Part::Name(n) => names.push(n),
            Part::Nested(ty) => {
                if !names.is_empty() {
                    out.push(quote!(&[#(#names),*]));
                    names.clear();
                }
                out.push(quote!(<#ty as ::hdgear::output::Record>::COLUMNS));
            }
        }
    }
    if !names.is_empty() {
        out.push(quote!(&[#(#names),*]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::expand;

    fn expanded(src: &str) -> syn::Result<String> {
        expand(&syn::parse_str(src).unwrap()).map(|t| t.to_string())
    }

    fn refused(src: &str) -> String {
        expanded(src).unwrap_err().to_string()
    }

    #[test]
    fn plain_names_and_nested_records_become_constant_parts() {
        let out = expanded(
            "struct R<'a, V = P> { #[serde(rename = \"type\")] kind: &'a str, \
             #[record(nested)] p: V, #[serde(skip)] h: f64, last: u32 }",
        )
        .unwrap();
        assert!(out.contains("for R < '_ , P >"), "{out}");
        assert!(out.contains("& [\"type\"]"), "{out}");
        assert!(
            out.contains("< P as :: hdgear :: output :: Record > :: COLUMNS"),
            "{out}"
        );
        assert!(out.contains("& [\"last\"]"), "{out}");
        assert!(!out.contains("\"h\""), "{out}");
    }

    #[test]
    fn what_would_make_the_columns_other_than_the_fields_is_refused() {
        for (src, why) in [
            ("struct R { #[serde(flatten)] m: M }", "not read"),
            (
                "struct R { #[serde(skip_serializing_if = \"f\")] m: f64 }",
                "not read",
            ),
            (
                "#[serde(rename_all = \"camelCase\")] struct R { m: f64 }",
                "container",
            ),
            ("struct R<V> { v: V }", "default"),
            ("struct R(f64);", "named fields"),
            ("enum R { A }", "struct"),
            ("struct R { #[record(flat)] m: f64 }", "nested"),
        ] {
            let e = refused(src);
            assert!(e.contains(why), "{src}: {e}");
        }
    }
}
