//! An emulated EtherCAT slave controller (ESC), sans-IO: EtherCAT frames in, the same frames out with
//! every datagram processed as a chain of slaves processes it (ETG.1000.4).
//!
//! - [`frame`]: the EtherCAT frame and its datagrams (view + emit);
//! - [`esc`]: one slave's ESC memory (registers and process RAM), its addresses, and the datagram
//!   commands with their working-counter rules; [`esc::Chain`] passes a frame through several slaves.
//!
//! Not in it yet: FMMU logical addressing (LRD/LWR/LRW answer with no slave taking part), SyncManager
//! mailboxes and buffers, the EEPROM interface, AL state machine, DC, and the raw-socket runtime.
#![deny(missing_docs)]

pub mod esc;
pub mod frame;
