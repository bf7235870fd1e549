//! Drive logic built on the object dictionary: the CiA 402 state machine, the B&R X67SM2436 "Ramp" axis
//! model and the AMCI SMD23K-B/SMD24K indexer model.
//!
//! This crate currently provides the shared dictionary access for the drive models; the models arrive with
//! their own modules.
#![deny(missing_docs)]

pub use od;
