//! An emulated EtherCAT slave controller (ESC), sans-IO: EtherCAT frames in, the same frames out with
//! every datagram processed as a chain of slaves processes it (ETG.1000.4).
//!
//! - [`frame`]: the EtherCAT frame and its datagrams (view + emit);
//! - [`esc`]: one slave's ESC memory (registers and process RAM), its addresses, and the datagram
//!   commands with their working-counter rules; [`esc::Chain`] passes a frame through several slaves.
//!
//! In it: the register commands, FMMU logical addressing (LRD/LWR/LRW, byte-granular), the EEPROM
//! interface reading an SII image (`od::sii`), the AL state machine with its SyncManager checks
//! ([`al`]). Not in it yet: SyncManager mailboxes and buffers, DC, the CoE mailbox, the SMD model's process data, and the raw-socket runtime.
#![deny(missing_docs)]

pub mod al;
pub mod esc;
pub mod frame;
pub mod smd;
