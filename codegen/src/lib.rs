//! `envc::env!`: a typed environment from a spec, checked at compile time.
//!
//! A thin shim over `envspec`: the macro loads and resolves the spec against its model exactly as the
//! runtime does, turns every diagnostic into a compile error (file, line, column, the line with a
//! caret, what was expected, a suggestion), and emits typed wrappers around the dynamic `envc::Env`
//! (one core, so typed and dynamic trajectories are the same by construction).
//!
//! ```text
//! envc::env!("specs/gymnasium/ant.toml");                       // type `AntV5` (from the id)
//! envc::env!(pub Go1 = "specs/examples/go1.toml",               // your own name ...
//!            xml_file = "menagerie/unitree_go1/scene.xml"); // ... and build-time overrides
//! ```
//!
//! Relative paths resolve against the calling crate's `CARGO_MANIFEST_DIR` (like `include_str!`);
//! `ENVC_MANIFEST_DIR_OVERRIDE` replaces it (used by the compile-fail tests, whose crates live
//! under `target/`).

mod docs;
mod expand;
mod multi_agent;

use std::path::{Path, PathBuf};

use proc_macro::TokenStream;
use syn::parse::{Parse, ParseStream};
use syn::{Ident, Lit, LitStr, Token, Visibility};

/// Generate a typed env from a spec file. See the crate docs and the README ("Add your own robot").
#[proc_macro]
pub fn env(input: TokenStream) -> TokenStream {
    let input = syn::parse_macro_input!(input as Input);
    expand::expand(input).into()
}

/// Typed per-agent observation and action types for one conf of a multi-agent spec:
/// `envc::multi_agent_env!(pub AntQuad = "specs/mamujoco/ant.toml", agent_conf = "4x2")`.
#[proc_macro]
pub fn multi_agent_env(input: TokenStream) -> TokenStream {
    let input = syn::parse_macro_input!(input as Input);
    multi_agent::expand(input).into()
}

pub(crate) struct Input {
    pub vis: Visibility,
    pub name: Option<Ident>,
    pub path: LitStr,
    pub overrides: Vec<(Ident, Lit)>,
}

impl Parse for Input {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let vis: Visibility = input.parse()?;
        let name = if input.peek(Ident) && input.peek2(Token![=]) {
            let n: Ident = input.parse()?;
            input.parse::<Token![=]>()?;
            Some(n)
        } else {
            None
        };
        let vis = match (&vis, &name) {
            // A bare `env!("…")` makes public types.
            (Visibility::Inherited, None) => syn::parse_quote!(pub),
            _ => vis,
        };
        let path: LitStr = input.parse().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected a spec path: `envc::env!(\"specs/my_robot.toml\")` or `envc::env!(pub MyRobot = \"specs/my_robot.toml\", param = value, ...)`",
            )
        })?;
        let mut overrides = vec![];
        while input.parse::<Option<Token![,]>>()?.is_some() {
            if input.is_empty() {
                break;
            }
            let key: Ident = input.parse()?;
            input.parse::<Token![=]>()?;
            let value: Lit = input.parse()?;
            overrides.push((key, value));
        }
        if !input.is_empty() {
            return Err(input.error("expected `, parameter = literal` or the end of the macro"));
        }
        Ok(Input {
            vis,
            name,
            path,
            overrides,
        })
    }
}

/// The directory relative spec paths resolve against.
pub(crate) fn manifest_root() -> PathBuf {
    std::env::var_os("ENVC_MANIFEST_DIR_OVERRIDE")
        .or_else(|| std::env::var_os("CARGO_MANIFEST_DIR"))
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("."))
}

/// `root/p` for a relative `p`, without `..` segments where the filesystem can resolve them.
pub(crate) fn absolute(root: &Path, p: &Path) -> PathBuf {
    let joined = if p.is_absolute() {
        p.to_path_buf()
    } else {
        root.join(p)
    };
    joined.canonicalize().unwrap_or(joined)
}

/// `include_bytes!` of every file envspec read while the macro expanded (the record of
/// [`envspec::source::Reader`]: the spec, its base or robot spec, a maze's map, the model and
/// every `<include>`), so editing any of them rebuilds the caller. Meshes and textures are
/// recorded without a hash and not tracked: MuJoCo reads them at run time and no generated code
/// depends on them.
pub(crate) fn track(root: &Path, reader: &envspec::source::Reader) -> proc_macro2::TokenStream {
    reader
        .files()
        .iter()
        .filter(|f| f.hash.is_some())
        .filter_map(|f| absolute(root, &f.path).to_str().map(str::to_string))
        .map(|f| quote::quote! { const _: &[u8] = include_bytes!(#f); })
        .collect()
}
