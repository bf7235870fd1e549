//! CANopen over EtherCAT (CoE) framing of ETG.1000.6 §5.6: the mailbox header (§5.6.1), the CoE header
//! (§5.6.2) and the SDO request and response frames that ride in a mailbox (§5.6.2.1–5.6.2.7), with
//! their longer data (a normal transfer carries as much as the mailbox holds), the complete-access bit,
//! and the EtherCAT abort codes (in [`AbortCode`](crate::AbortCode)).
//!
//! Each wire type has a typed representation with `parse` (which names what is wrong) and `emit`.
//!
//! [`CoeServer`] is the SDO server of an EtherCAT slave: the CiA 301 SDO server of [`crate::sdo`] on
//! the same [`Dictionary`](crate::Dictionary), reached through mailboxes; another protocol (FoE)
//! shares its mailbox through a [`MailboxService`].

pub mod complete;
pub mod info;
pub mod mailbox;
pub mod sdo;
pub mod server;

pub use mailbox::{
    CoeHeader, CoeService, FramingError, MailboxHeader, MailboxType, MAILBOX_HEADER_LEN,
};
pub use sdo::{CoeSdo, CoeSdoCommand, CoeSdoError};
pub use server::{
    is_pdo_configuration, CoeServer, MailboxService, ServiceAnswer, MAX_MAILBOX_SIZE,
    MIN_MAILBOX_SIZE,
};
