//! Helpers shared by the integration tests of `od`: the saved fuzz corpora and their changed copies, and
//! random parts of descriptions for the write → read properties. Each test file uses `mod support;` and
//! takes what it needs.
#![allow(dead_code)]

pub mod corpus;
pub mod random;
