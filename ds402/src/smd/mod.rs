//! The AMCI SMD23K-B / SMD24K integrated stepper indexer (seed 000, the AMCI manual).
//!
//! - [`profile`]: the move-profile maths of Reference 3 (linear and S-curve acceleration, trapezoidal and
//!   triangular profiles, peak speed, phase times and distances);
//! - [`config`]: the configuration data of Reference 5 (`8010:01–07`), its validity rules and the
//!   CFG_Word_0 / CFG_Word_1 calculator of table R5.3;
//! - [`indexer`]: the unit in Command Mode — commands, moves, status words;
//! - with feature `cli`: `simulate`, `smd simulate`'s offline runs of scripts against the indexer, as
//!   tables and charts; `plot`, SVG charts; `cli`, the `smd` command line.

#[cfg(feature = "cli")]
pub mod cli;
pub mod config;
pub mod indexer;
#[cfg(feature = "cli")]
pub mod plot;
pub mod profile;
#[cfg(feature = "cli")]
pub mod simulate;
