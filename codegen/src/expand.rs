//! Spec → tokens: the typed Config, Obs, Action, Info and env types.

use std::path::Path;

use envspec::params::decl_type;
use envspec::{Diagnostics, Override, ParamType, ParamValue, ResolvedSpec, Spec};
use proc_macro2::{Literal, Span, TokenStream};
use quote::{format_ident, quote};
use syn::{Ident, Lit, Visibility};

use crate::{Input, absolute, docs, manifest_root, track};

pub(crate) fn expand(input: Input) -> TokenStream {
    let root = manifest_root();
    let spec_path = absolute(&root, Path::new(&input.path.value()));
    let lit_span = input.path.span();
    // Override problems point at the macro argument; everything else at the spec path.
    let arg_spans: Vec<(String, Span)> = input
        .overrides
        .iter()
        .map(|(k, _)| (format!("`{k}`"), k.span()))
        .collect();
    let errors = |d: Diagnostics| render_errors(&d, &root, lit_span, &arg_spans);

    // Every file the spec reads, through envspec's one reader, recorded for `track`.
    let mut reader = envspec::source::Reader::disk();
    let spec = match reader.run(|| Spec::load(&spec_path)) {
        Ok(s) => s,
        // The files read are still dependencies: fixing them must trigger a rebuild.
        Err(d) => {
            let mut out = errors(d);
            out.extend(track(&root, &reader));
            return out;
        }
    };
    let overrides = build_overrides(&spec, &input.overrides, &root);
    let resolved = match reader.run(|| envspec::resolve(&spec, &overrides)) {
        Ok(r) => r,
        Err(d) => {
            let mut out = errors(d);
            out.extend(track(&root, &reader));
            return out;
        }
    };
    let name = match &input.name {
        Some(n) => n.clone(),
        None => match type_name(&resolved.id) {
            Some(n) => Ident::new(&n, lit_span),
            None => {
                return syn::Error::new(
                    lit_span,
                    format!(
                        "cannot make a type name from the env id `{}`; name it: `envc::env!(pub MyEnv = \"...\")`",
                        resolved.id
                    ),
                )
                .to_compile_error();
            }
        },
    };
    match generate(&input, &name, &spec, &resolved, &spec_path) {
        Ok(mut tokens) => {
            tokens.extend(track(&root, &reader));
            tokens
        }
        Err(e) => e.to_compile_error(),
    }
}

/// Every diagnostic as its own compile error (all at once), paths shown relative to the crate.
fn render_errors(d: &Diagnostics, root: &Path, span: Span, args: &[(String, Span)]) -> TokenStream {
    let prefix = format!("{}/", root.display());
    let canon = root
        .canonicalize()
        .map(|p| format!("{}/", p.display()))
        .unwrap_or_else(|_| prefix.clone());
    d.iter()
        .map(|diag| {
            let text = diag.to_string().replace(&canon, "").replace(&prefix, "");
            // rustc prints `error: `; keep the stable code right after it.
            let text = text
                .strip_prefix("error[")
                .and_then(|t| t.split_once("]: "))
                .map(|(code, rest)| format!("{code}: {rest}"))
                .unwrap_or(text.clone());
            let at = match diag.code {
                envspec::Code::E0202 | envspec::Code::E0203 => args
                    .iter()
                    .find(|(name, _)| diag.message.contains(name.as_str()))
                    .map(|(_, s)| *s)
                    .unwrap_or(span),
                _ => span,
            };
            syn::Error::new(at, text.trim_end()).to_compile_error()
        })
        .collect()
}

/// Macro arguments → overrides, typed by the parameter's declaration.
fn build_overrides(spec: &Spec, args: &[(Ident, Lit)], root: &Path) -> Vec<Override> {
    args.iter()
        .map(|(key, lit)| {
            let name = key.to_string();
            let ty = spec.param(&name).map(decl_type);
            match (lit, ty) {
                (Lit::Str(s), Some(ParamType::Path)) => {
                    let p = absolute(root, Path::new(&s.value()));
                    Override::value(&name, ParamValue::Str(p.display().to_string()))
                }
                (Lit::Str(s), Some(ParamType::String | ParamType::Body)) => {
                    Override::value(&name, ParamValue::Str(s.value()))
                }
                (Lit::Str(s), _) => Override::text(&name, &s.value()),
                (other, _) => Override::text(&name, &quote!(#other).to_string()),
            }
        })
        .collect()
}

/// `Ant-v5` → `AntV5`, `go1_walk-v0` → `Go1WalkV0`.
fn type_name(id: &str) -> Option<String> {
    let mut out = String::new();
    for part in id.split(|c: char| !c.is_ascii_alphanumeric()) {
        let mut cs = part.chars();
        if let Some(c) = cs.next() {
            out.push(c.to_ascii_uppercase());
            out.extend(cs);
        }
    }
    let ok = out.chars().next().is_some_and(|c| c.is_ascii_alphabetic());
    ok.then_some(out)
}

/// A field or method name from a spec name (raw identifiers for keywords).
fn ident(name: &str, what: &str) -> syn::Result<Ident> {
    if syn::parse_str::<Ident>(name).is_ok() {
        return Ok(Ident::new(name, Span::call_site()));
    }
    if let Ok(id) = syn::parse_str::<Ident>(&format!("r#{name}")) {
        return Ok(id);
    }
    Err(syn::Error::new(
        Span::call_site(),
        format!("the {what} `{name}` is not a valid Rust identifier; rename it in the spec"),
    ))
}

pub(crate) fn float(x: f64) -> TokenStream {
    if x.is_nan() {
        quote!(f64::NAN)
    } else if x == f64::INFINITY {
        quote!(f64::INFINITY)
    } else if x == f64::NEG_INFINITY {
        quote!(f64::NEG_INFINITY)
    } else {
        let l = Literal::f64_suffixed(x);
        quote!(#l)
    }
}

/// The Rust type and value of a parameter.
fn param_type(ty: ParamType) -> TokenStream {
    match ty {
        ParamType::Bool => quote!(bool),
        ParamType::Int => quote!(i64),
        ParamType::Float => quote!(f64),
        ParamType::Range => quote!((f64, f64)),
        ParamType::String | ParamType::Table => quote!(::std::string::String),
        ParamType::Path => quote!(::std::path::PathBuf),
        ParamType::Body => quote!(::envc::typed::BodyRef),
        ParamType::Names => quote!(::std::vec::Vec<::std::string::String>),
    }
}

fn param_value(ty: ParamType, v: &ParamValue) -> TokenStream {
    match (ty, v) {
        (_, ParamValue::Bool(b)) => quote!(#b),
        (ParamType::Float, ParamValue::Int(i)) => float(*i as f64),
        (ParamType::Body, ParamValue::Int(i)) => quote!(::envc::typed::BodyRef::Id(#i)),
        (ParamType::Body, ParamValue::Str(s)) => {
            quote!(::envc::typed::BodyRef::Name(::std::string::String::from(#s)))
        }
        (_, ParamValue::Int(i)) => quote!(#i),
        (_, ParamValue::Float(x)) => float(*x),
        (_, ParamValue::Range(a, b)) => {
            let (a, b) = (float(*a), float(*b));
            quote!((#a, #b))
        }
        (ParamType::Path, ParamValue::Str(s)) => quote!(::std::path::PathBuf::from(#s)),
        (_, ParamValue::Str(s)) | (_, ParamValue::Table(s)) => {
            quote!(::std::string::String::from(#s))
        }
        (_, ParamValue::Names(n)) => quote!(::std::vec![#(::std::string::String::from(#n)),*]),
    }
}

/// The typed env's items, in order: Config, Obs, Action, Info, ResetInfo, Step and the env.
fn generate(
    input: &Input,
    name: &Ident,
    spec: &Spec,
    r: &ResolvedSpec,
    spec_path: &Path,
) -> syn::Result<TokenStream> {
    let vis = &input.vis;
    let names = Names {
        env: name,
        config: format_ident!("{}Config", name),
        obs: format_ident!("{}Obs", name),
        action: format_ident!("{}Action", name),
        info: format_ident!("{}Info", name),
        reset_info: format_ident!("{}ResetInfo", name),
        step: format_ident!("{}Step", name),
    };
    let config_def = config_items(vis, &names, r)?;
    let obs_def = obs_items(vis, &names, spec, r)?;
    let action_def = action_items(vis, &names, r);
    // Info: step info has every key, reset info the `at_reset` ones.
    let info_def = info_struct(vis, r, r.info.iter().collect(), &names.info, "step info")?;
    let reset_info_def = info_struct(
        vis,
        r,
        r.reset_info().collect(),
        &names.reset_info,
        "reset info",
    )?;
    let step_def = step_items(vis, &names);
    let env_def = env_items(vis, &names, spec, r, spec_path);
    Ok(quote! {
        #config_def
        #obs_def
        #action_def
        #info_def
        #reset_info_def
        #step_def
        #env_def
    })
}

/// The names of the generated types.
struct Names<'a> {
    env: &'a Ident,
    config: Ident,
    obs: Ident,
    action: Ident,
    info: Ident,
    reset_info: Ident,
    step: Ident,
}

/// Config: one field per parameter; defaults are the spec's (after build-time overrides).
fn config_items(vis: &Visibility, names: &Names, r: &ResolvedSpec) -> syn::Result<TokenStream> {
    let config = &names.config;
    let id = &r.id;
    let mut fields = vec![];
    let mut defaults = vec![];
    let mut builders = vec![];
    let mut to_overrides = vec![];
    // Fixed parameters are part of the spec but not of its constructor: no Config field.
    for p in r.params.iter().filter(|p| !p.fixed) {
        let f = ident(&p.name, "parameter")?;
        let ty = param_type(p.ty);
        let pname = &p.name;
        // xml_file is always passed as an absolute path: the typed env may run from any directory.
        let value = if p.name == "xml_file" {
            let m = r.model_path.display().to_string();
            quote!(::std::path::PathBuf::from(#m))
        } else {
            param_value(p.ty, &p.value)
        };
        let spec_default = param_value(p.ty, &p.default);
        let doc = docs::param_doc(p);
        fields.push(quote! { #[doc = #doc] pub #f: #ty });
        defaults.push(quote! { #f: #value });
        let bdoc = format!("Set `{pname}` (builder style).");
        builders.push(quote! {
            #[doc = #bdoc]
            pub fn #f(mut self, value: impl ::core::convert::Into<#ty>) -> Self {
                self.#f = value.into();
                self
            }
        });
        let always = p.name == "xml_file";
        to_overrides.push(quote! {
            if #always || self.#f != #spec_default {
                out.push(::envc::Override::value(#pname, ::envc::typed::ToParam::to_param(&self.#f)));
            }
        });
    }
    let config_doc = format!(
        "Parameters of `{id}`: one field per spec parameter, defaults from the spec.\n\n\
         Build with struct update (`{config} {{ ctrl_cost_weight: 0.1, ..Default::default() }}`) or \
         builder style (`{config}::default().ctrl_cost_weight(0.1)`). Values are checked like the \
         spec when the env is built."
    );
    Ok(quote! {
        #[doc = #config_doc]
        #[derive(Clone, Debug, PartialEq)]
        #vis struct #config { #(#fields,)* }

        impl ::core::default::Default for #config {
            fn default() -> Self {
                Self { #(#defaults,)* }
            }
        }

        impl #config {
            #(#builders)*

            /// The parameters that differ from the spec's defaults, as overrides (`xml_file` always,
            /// as an absolute path).
            #[allow(clippy::cmp_owned)] // compared with the spec's defaults, written as values
            pub fn to_overrides(&self) -> ::std::vec::Vec<::envc::Override> {
                let mut out = ::std::vec::Vec::new();
                #(#to_overrides)*
                out
            }
        }
    })
}

/// Observation: one accessor per declared segment (switched-off segments give empty slices).
fn obs_items(
    vis: &Visibility,
    names: &Names,
    spec: &Spec,
    r: &ResolvedSpec,
) -> syn::Result<TokenStream> {
    let (obs, name, id) = (&names.obs, names.env, &r.id);
    let mut accessors = vec![];
    for (i, s) in spec.observation.iter().enumerate() {
        let f = ident(&s.name, "observation segment")?;
        let doc = docs::segment_doc(r, &s.name);
        accessors.push(quote! {
            #[doc = #doc]
            pub fn #f(&self) -> &'a [f64] {
                &self.data[self.layout[#i].clone()]
            }
        });
    }
    let obs_doc = format!(
        "An observation of `{id}`: named, typed access to each segment (see [`{name}`] for the layout)."
    );
    Ok(quote! {
        #[doc = #obs_doc]
        #[derive(Clone, Copy, Debug)]
        #vis struct #obs<'a> {
            data: &'a [f64],
            layout: &'a [::core::ops::Range<usize>],
        }

        impl<'a> #obs<'a> {
            /// The whole observation vector.
            pub fn as_slice(&self) -> &'a [f64] {
                self.data
            }
            #(#accessors)*
        }

        impl ::core::ops::Deref for #obs<'_> {
            type Target = [f64];
            fn deref(&self) -> &[f64] {
                self.data
            }
        }
    })
}

/// Action: a fixed-size array with the actuators' names.
fn action_items(vis: &Visibility, names: &Names, r: &ResolvedSpec) -> TokenStream {
    let action = &names.action;
    let act_dim = r.act_dim();
    // An end-effector action is Cartesian, not one value per actuator.
    let act_names: Vec<&str> = match &r.manipulation.end_effector {
        Some(e) => ["dx", "dy", "dz", "gripper"][..e.act_dim()].to_vec(),
        None => r.model.actuators.iter().map(docs::actuator_label).collect(),
    };
    let action_doc = docs::action_doc(r, names.env);
    quote! {
        #[doc = #action_doc]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #vis struct #action(
            /// One value per actuator, in the spec's action order.
            pub [f64; #act_dim],
        );

        impl #action {
            /// Number of actuators.
            pub const ACT_DIM: usize = #act_dim;
            /// Actuator names in action order (an unnamed actuator by the joint, tendon or site it drives).
            pub const ACTUATORS: [&'static str; #act_dim] = [#(#act_names),*];
            /// All zeros.
            pub fn zeros() -> Self {
                Self([0.0; #act_dim])
            }
            /// The value for the actuator `name` (None for an unknown name).
            pub fn get_mut(&mut self, name: &str) -> ::core::option::Option<&mut f64> {
                let i = Self::ACTUATORS.iter().position(|a| *a == name)?;
                ::core::option::Option::Some(&mut self.0[i])
            }
        }

        impl ::core::default::Default for #action {
            fn default() -> Self {
                Self::zeros()
            }
        }

        impl ::core::convert::From<[f64; #act_dim]> for #action {
            fn from(a: [f64; #act_dim]) -> Self {
                Self(a)
            }
        }
    }
}

/// An info struct: one typed field per key of `items`.
fn info_struct(
    vis: &Visibility,
    r: &ResolvedSpec,
    items: Vec<&envspec::ir::InfoItem>,
    tyname: &Ident,
    what: &str,
) -> syn::Result<TokenStream> {
    let id = &r.id;
    let mut fs = vec![];
    let mut reads = vec![];
    let mut keys = vec![];
    let mut gets = vec![];
    for it in items {
        let f = ident(&it.key, "info key")?;
        let key = &it.key;
        let doc = docs::info_doc(r, it);
        keys.push(key.clone());
        gets.push(if it.len == 1 {
            quote! { #key => ::core::option::Option::Some(::core::slice::from_ref(&self.#f)) }
        } else {
            quote! { #key => ::core::option::Option::Some(&self.#f[..]) }
        });
        if it.len == 1 {
            fs.push(quote! { #[doc = #doc] pub #f: f64 });
            reads.push(quote! { #f: ::envc::typed::info_scalar(info, #key) });
        } else {
            let n = it.len;
            fs.push(quote! { #[doc = #doc] pub #f: [f64; #n] });
            reads.push(quote! { #f: ::envc::typed::info_array::<#n>(info, #key) });
        }
    }
    let doc = format!(
        "The {what} of `{id}`, one typed field per key (NaN when an override removed a key)."
    );
    Ok(quote! {
        #[doc = #doc]
        #[derive(Clone, Copy, Debug, PartialEq)]
        #vis struct #tyname { #(#fs,)* }
        impl #tyname {
            /// Copy the values out of a dynamic info view.
            #[allow(unused_variables)]
            pub fn from_info(info: &::envc::Info<'_>) -> Self {
                Self { #(#reads,)* }
            }
            /// The keys, in the spec's info order.
            pub const KEYS: &'static [&'static str] = &[#(#keys),*];
            /// A value by key, as the dynamic info gives it.
            pub fn get(&self, key: &str) -> ::core::option::Option<&[f64]> {
                match key {
                    #(#gets,)*
                    _ => ::core::option::Option::None,
                }
            }
        }
    })
}

/// Step: the typed result of `step`.
fn step_items(vis: &Visibility, names: &Names) -> TokenStream {
    let (step, obs, info, name) = (&names.step, &names.obs, &names.info, names.env);
    let step_doc = format!("The result of [`{name}::step`]: typed observation and info.");
    quote! {
        #[doc = #step_doc]
        #[derive(Clone, Copy, Debug)]
        #vis struct #step<'a> {
            /// The observation after the step, a view of the env's buffer.
            pub obs: #obs<'a>,
            /// The step's reward, the sum of the spec's reward terms.
            pub reward: f64,
            /// Whether the episode ended in a terminal state (health or a termination term).
            pub terminated: bool,
            /// Whether the time limit ended the episode.
            pub truncated: bool,
            /// The step's info terms.
            pub info: #info,
        }
    }
}

/// The env type: constructors, `reset` and `step` over the typed items, and the dynamic env
/// underneath.
fn env_items(
    vis: &Visibility,
    names: &Names,
    spec: &Spec,
    r: &ResolvedSpec,
    spec_path: &Path,
) -> TokenStream {
    let Names {
        env: name,
        config,
        obs,
        action,
        info,
        reset_info,
        step,
    } = names;
    let id = &r.id;
    let spec_file = spec_path.display().to_string();
    let obs_dim = r.obs_dim;
    let act_dim = r.act_dim();
    let seg_names: Vec<&str> = spec.observation.iter().map(|s| s.name.as_str()).collect();
    let env_doc = docs::env_doc(r, &spec_display(spec_path));
    quote! {
        #[doc = #env_doc]
        #vis struct #name {
            env: ::envc::Env,
            layout: ::std::vec::Vec<::core::ops::Range<usize>>,
        }

        impl #name {
            /// The env id.
            pub const ID: &'static str = #id;
            /// The spec file this type was generated from.
            pub const SPEC_PATH: &'static str = #spec_file;
            /// Observation size with the default parameters (flags such as
            /// `exclude_current_positions_from_observation` change it: see `obs_dim()`).
            pub const OBS_DIM: usize = #obs_dim;
            /// Action size (the model's actuator count).
            pub const ACT_DIM: usize = #act_dim;
            const SPEC_TEXT: &'static str = include_str!(#spec_file);
            const SEGMENTS: &'static [&'static str] = &[#(#seg_names),*];

            /// Build the env with the given parameters (checked like the spec).
            pub fn new(config: &#config) -> ::core::result::Result<Self, ::envc::EnvError> {
                let env = ::envc::typed::build(Self::SPEC_PATH, Self::SPEC_TEXT, &config.to_overrides(), Self::ACT_DIM)?;
                let layout = ::envc::typed::segment_ranges(env.spec(), Self::SEGMENTS);
                ::core::result::Result::Ok(Self { env, layout })
            }

            /// Build the env with the default parameters.
            pub fn make() -> ::core::result::Result<Self, ::envc::EnvError> {
                Self::new(&#config::default())
            }

            /// Gymnasium `reset(seed=…)`: typed observation and reset info.
            pub fn reset(&mut self, seed: ::core::option::Option<u64>) -> (#obs<'_>, #reset_info) {
                let (data, info) = self.env.reset(seed);
                let info = #reset_info::from_info(&info);
                (#obs { data, layout: &self.layout }, info)
            }

            /// Gymnasium `step` with a typed action.
            pub fn step(&mut self, action: &#action) -> ::core::result::Result<#step<'_>, ::envc::EnvError> {
                let s = self.env.step(&action.0)?;
                ::core::result::Result::Ok(#step {
                    obs: #obs { data: s.obs, layout: &self.layout },
                    reward: s.reward,
                    terminated: s.terminated,
                    truncated: s.truncated,
                    info: #info::from_info(&s.info),
                })
            }

            /// Per-actuator control range `(low, high)` from the compiled model.
            pub fn ctrl_range(&self) -> [(f64, f64); #act_dim] {
                let sp = self.env.action_space();
                ::core::array::from_fn(|i| (sp.low[i], sp.high[i]))
            }

            /// The dynamic env underneath (same core).
            pub fn inner(&self) -> &::envc::Env {
                &self.env
            }
            /// The dynamic env underneath, mutably.
            pub fn inner_mut(&mut self) -> &mut ::envc::Env {
                &mut self.env
            }
            /// Unwrap into the dynamic env.
            pub fn into_inner(self) -> ::envc::Env {
                self.env
            }
        }

        impl ::envc::Environment for #name {
            fn env(&self) -> &::envc::Env {
                &self.env
            }
            fn env_mut(&mut self) -> &mut ::envc::Env {
                &mut self.env
            }
        }
    }
}

/// The spec path as shown in docs: relative to the crate when possible.
fn spec_display(p: &Path) -> String {
    let root = manifest_root();
    let root = root.canonicalize().unwrap_or(root);
    p.strip_prefix(&root).unwrap_or(p).display().to_string()
}
