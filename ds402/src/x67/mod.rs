//! The B&R X67SM2436 two-axis stepper module in function model "Ramp" (seed 002, the B&R data sheet).
//!
//! - [`ramp`]: the ramp generator of one axis (speed, acceleration, reversing loop, jerk limitation);
//! - [`current`]: the motor current of one axis (holding, nominal and maximum current, the 100 ms hold,
//!   full-step threshold);
//! - [`errors`]: an axis's error-code register with the module's over-temperature cut-off;
//! - [`axis`]: one Ramp axis (its CiA 402 state machine variant, modes, homing, limits);
//! - [`module`], [`registers`] and [`motor`]: the whole module with its registers and simulated motors.

pub mod axis;
pub mod current;
pub mod errors;
pub mod module;
pub mod motor;
pub mod ramp;
pub mod registers;
