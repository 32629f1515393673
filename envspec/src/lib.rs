//! envc spec language.
