//! Drive logic built on the object dictionary: the CiA 402 state machine, the B&R X67SM2436 "Ramp" axis
//! model and the AMCI SMD23K-B/SMD24K indexer model.
//!
//! [`cia402`] is the generic CiA 402 state machine (control-word commands, status word, transitions) as the
//! X67SM2436 runs it; [`x67`] is the X67SM2436 "Ramp" module (ramp generator, motor current, error
//! register, axes, registers, simulated motors); [`smd`] is the AMCI SMD23K-B/SMD24K indexer;
//! [`drive`] is a CiA 402 drive made from any description, and [`generic`] the drives of a
//! description as one [`od::hook::Device`], which the CANopen node and the EtherCAT unit both run.
#![deny(missing_docs)]

pub mod cia402;
pub mod drive;
pub mod generic;
pub mod smd;
pub mod x67;

pub use od;
