//! Helpers shared by the integration tests of `od`; each test file uses `mod support;` and takes what it
//! needs.
#![allow(dead_code)]

pub mod corpus;
