//! `envc::multi_agent_env!`: typed per-agent observation and action types for one conf of a
//! multi-agent spec (a spec with `[agents]`, see `envspec::multi_agent`).
//!
//! ```text
//! envc::multi_agent_env!(pub AntQuad = "specs/mamujoco/ant.toml", agent_conf = "4x2", agent_obsk = 1);
//! // AntQuad (the env), AntQuadObs / AntQuadActions (one field per agent),
//! // AntQuadAgent0Obs ([f64; N] with one accessor per observation segment),
//! // AntQuadAgent0Action (one f64 field per node, in the agent's action order), ...
//! ```

use std::path::Path;

use envspec::multi_agent::MultiAgentSpec;
use envspec::{Diagnostics, Override};
use proc_macro2::{Literal, Span, TokenStream};
use quote::{format_ident, quote};
use syn::Ident;

use crate::{Input, absolute, manifest_root, track};

fn errors(d: &Diagnostics, span: Span) -> TokenStream {
    d.iter()
        .map(|diag| syn::Error::new(span, diag.to_string().trim_end()).to_compile_error())
        .collect()
}

/// A Rust identifier from a node or segment name (`k0.hip1.qpos#1` → `k0_hip1_qpos_1`).
fn ident(s: &str) -> String {
    let mut out: String = s
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    while out.contains("__") {
        out = out.replace("__", "_");
    }
    let out = out.trim_matches('_').to_string();
    if out.is_empty() || out.starts_with(|c: char| c.is_ascii_digit()) {
        format!("n_{out}")
    } else {
        out
    }
}

pub(crate) fn expand(input: Input) -> TokenStream {
    let root = manifest_root();
    let spec_path = absolute(&root, Path::new(&input.path.value()));
    let span = input.path.span();
    let overrides = build_overrides(&input, &root);
    // The spec, its base, the model and its includes, through envspec's one reader (`track`).
    let mut reader = envspec::source::Reader::disk();
    let spec = match reader.run(|| envspec::multi_agent::load(&spec_path, &overrides)) {
        Ok(s) => s,
        Err(d) => {
            let mut out = errors(&d, span);
            out.extend(track(&root, &reader));
            return out;
        }
    };
    let Some(name) = input.name.clone() else {
        return syn::Error::new(
            span,
            "name the env: `envc::multi_agent_env!(pub MyAgents = \"specs/...\", agent_conf = \"...\")`",
        )
        .to_compile_error();
    };
    let vis = &input.vis;
    let mut items = TokenStream::new();
    let mut agents = vec![];
    for (i, a) in spec.agents.iter().enumerate() {
        let agent = AgentTypes {
            obs: format_ident!("{}Agent{}Obs", name, i),
            act: format_ident!("{}Agent{}Action", name, i),
            field: format_ident!("{}", ident(&a.name)),
        };
        items.extend(agent_items(vis, &spec, a, &agent));
        agents.push(agent);
    }
    items.extend(env_items(
        vis, &name, &spec, &agents, &spec_path, &overrides,
    ));
    items.extend(track(&root, &reader));
    items
}

/// Macro arguments → overrides (`xml_file` made absolute).
fn build_overrides(input: &Input, root: &Path) -> Vec<Override> {
    input
        .overrides
        .iter()
        .map(|(k, lit)| {
            let v = match lit {
                syn::Lit::Str(s) if k == "xml_file" => {
                    absolute(root, Path::new(&s.value())).display().to_string()
                }
                syn::Lit::Str(s) => s.value(),
                other => quote!(#other).to_string(),
            };
            Override::text(&k.to_string(), &v)
        })
        .collect()
}

/// One agent's generated types and its field in the all-agents structs.
struct AgentTypes {
    obs: Ident,
    act: Ident,
    field: Ident,
}

/// One agent's observation type (an accessor per segment) and action type (a field per node).
fn agent_items(
    vis: &syn::Visibility,
    spec: &MultiAgentSpec,
    a: &envspec::multi_agent::Agent,
    t: &AgentTypes,
) -> TokenStream {
    let (obs_ty, act_ty) = (&t.obs, &t.act);
    let dim = Literal::usize_unsuffixed(a.obs_dim);
    let nact = Literal::usize_unsuffixed(a.actions.len());
    let accessors = a.observation.iter().map(|s| {
        let f = format_ident!("{}", ident(&s.name));
        let (lo, hi) = (s.offset, s.offset + s.len());
        let doc = format!("`[{lo}:{hi}]` {}", s.element_names().join(", "));
        quote! {
            #[doc = #doc]
            pub fn #f(&self) -> &[f64] { &self.0[#lo..#hi] }
        }
    });
    let obs_doc = format!(
        "{}'s observation ({} float64), conf `{}`, k = {}.",
        a.name, a.obs_dim, spec.conf, spec.k
    );
    let act_names: Vec<_> = a
        .nodes
        .iter()
        .map(|n| format_ident!("{}", ident(n)))
        .collect();
    let act_docs: Vec<String> = a
        .nodes
        .iter()
        .zip(&a.actions)
        .zip(&a.actuators)
        .map(|((n, g), act)| format!("node `{n}`: global action[{g}], actuator {act}"))
        .collect();
    let act_doc = format!(
        "{}'s action: one value per node, in its action order.",
        a.name
    );
    quote! {
        #[doc = #obs_doc]
        #[derive(Clone, Debug, PartialEq)]
        #vis struct #obs_ty(pub [f64; #dim]);
        impl #obs_ty {
            pub const DIM: usize = #dim;
            #(#accessors)*
        }
        #[doc = #act_doc]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #vis struct #act_ty { #( #[doc = #act_docs] pub #act_names: f64, )* }
        impl #act_ty {
            pub const DIM: usize = #nact;
            pub fn to_array(&self) -> [f64; #nact] { [#(self.#act_names),*] }
        }
    }
}

/// Every agent's observations and actions, the step result and the env over the dynamic one.
fn env_items(
    vis: &syn::Visibility,
    name: &Ident,
    spec: &MultiAgentSpec,
    agents: &[AgentTypes],
    spec_path: &Path,
    overrides: &[Override],
) -> TokenStream {
    let path_str = spec_path.display().to_string();
    let ov_names: Vec<String> = overrides.iter().map(|o| o.name.clone()).collect();
    let ov_values: Vec<String> = overrides
        .iter()
        .map(|o| match &o.value {
            envspec::OverrideValue::Text(t) => t.clone(),
            envspec::OverrideValue::Value(v) => v.to_string(),
        })
        .collect();
    let obs_fields: Vec<&Ident> = agents.iter().map(|a| &a.field).collect();
    let act_fields = &obs_fields;
    let obs_types: Vec<&Ident> = agents.iter().map(|a| &a.obs).collect();
    let act_types: Vec<&Ident> = agents.iter().map(|a| &a.act).collect();
    let obs_all = format_ident!("{}Obs", name);
    let act_all = format_ident!("{}Actions", name);
    let step_ty = format_ident!("{}Step", name);
    let n_agents = spec.agents.len();
    let idx: Vec<usize> = (0..n_agents).collect();
    let agent_names: Vec<&str> = spec.agents.iter().map(|a| a.name.as_str()).collect();
    let state_dim = spec.state_dim();
    let env_doc = format!(
        "Typed multi-agent env `{}` (conf `{}`, k = {}) over {}, from {}.",
        spec.id, spec.conf, spec.k, spec.base.id, path_str
    );
    quote! {
        /// Every agent's observation.
        #[derive(Clone, Debug, PartialEq)]
        #vis struct #obs_all { #( pub #obs_fields: #obs_types, )* }
        /// Every agent's action.
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #vis struct #act_all { #( pub #act_fields: #act_types, )* }
        /// One step's result (reward, terminated, truncated are shared by all agents).
        #[derive(Clone, Debug)]
        #vis struct #step_ty { pub obs: #obs_all, pub reward: f64, pub terminated: bool, pub truncated: bool }

        #[doc = #env_doc]
        #vis struct #name { inner: ::envc::multi_agent::MultiAgentEnv }
        impl #name {
            pub const AGENTS: [&'static str; #n_agents] = [#(#agent_names),*];
            pub const STATE_DIM: usize = #state_dim;
            pub fn new() -> Result<Self, ::envc::EnvError> {
                let o = [#(::envc::Override::text(#ov_names, #ov_values)),*];
                Ok(Self { inner: ::envc::multi_agent::MultiAgentEnv::from_spec_file(#path_str, &o)? })
            }
            /// The dynamic env underneath.
            pub fn dynamic(&self) -> &::envc::multi_agent::MultiAgentEnv { &self.inner }
            fn typed_obs(&self) -> #obs_all {
                let o = self.inner.observations();
                #obs_all { #( #obs_fields: #obs_types(o[#idx].as_slice().try_into().expect("generated size")), )* }
            }
            pub fn reset(&mut self, seed: Option<u64>) -> #obs_all {
                self.inner.reset(seed);
                self.typed_obs()
            }
            pub fn step(&mut self, actions: &#act_all) -> Result<#step_ty, ::envc::EnvError> {
                let a = [#(actions.#act_fields.to_array().to_vec()),*];
                let refs: Vec<&[f64]> = a.iter().map(Vec::as_slice).collect();
                let s = self.inner.step(&refs)?;
                let (reward, terminated, truncated) = (s.reward, s.terminated, s.truncated);
                Ok(#step_ty { obs: self.typed_obs(), reward, terminated, truncated })
            }
            /// The global state (the base env's observation).
            pub fn state(&self) -> &[f64] { self.inner.state() }
        }
    }
}
