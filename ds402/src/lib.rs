//! Drive logic built on the object dictionary: the CiA 402 state machine, the B&R X67SM2436 "Ramp" axis
//! model and the AMCI SMD23K-B/SMD24K indexer model.
//!
//! [`cia402`] is the generic CiA 402 state machine (control-word commands, status word, transitions) as the
//! X67SM2436 runs it; [`ramp`] is the ramp generator of one X67SM2436 axis (speed, acceleration, reversing
//! loop, jerk limitation); [`current`] is the motor current of one axis (holding, nominal and maximum
//! current, the 100 ms hold, full-step threshold); [`errors`] is an axis's error-code register with the
//! module's over-temperature cut-off; [`axis`], [`module`], [`registers`] and [`motor`] make up the
//! X67SM2436 "Ramp" module. [`smd`] is the AMCI SMD23K-B/SMD24K indexer.
#![deny(missing_docs)]

pub mod axis;
pub mod cia402;
pub mod current;
pub mod errors;
pub mod module;
pub mod motor;
pub mod ramp;
pub mod registers;
pub mod smd;

pub use od;
