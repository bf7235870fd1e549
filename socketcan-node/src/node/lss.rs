//! The LSS slave (CiA 305 "Layer setting services"): switch state global and selective, configure
//! node-ID and bit timing, activate bit timing, store configuration, inquire identity and node-ID,
//! identify (non-)configured remote slaves, and Fastscan.
//!
//! A pure state machine: [`LssSlave::handle`] takes the eight data bytes of a request (COB-ID
//! [`LSS_REQUEST`], 0x7E5) and returns the answer to send (COB-ID [`LSS_RESPONSE`], 0x7E4), if any,
//! with what the node has to do ([`LssAction`]). The node owns the consequences: it makes a pending
//! node-ID active at its next NMT reset communication, or at once when it had none (CiA 305 §8.3.1,
//! "an LSS slave with node-ID 0xFF ... shall perform NMT reset communication when switched to the
//! waiting state").
//!
//! Choices where CiA 305 leaves room:
//! - Frames of another length than 8 are not LSS requests and are ignored, as are reserved command
//!   specifiers.
//! - Configure node-ID, configure and activate bit timing, store configuration and the inquire
//!   services are answered only in the configuration state (§8.3); the identify services and Fastscan
//!   in either state, Fastscan only by a slave without a node-ID and in the waiting state (§8.4.4).
//! - Bit timing: table 0 (the CiA 301 table), indices 0–4 and 6–8 (1000 … 10 kbit/s; index 5 is
//!   reserved in CiA 301 and is refused, as is automatic detection, 9); the value is kept and reported,
//!   the virtual bus has no bit rate.
//! - Store configuration answers "not supported" (1) when the node has no storage for it.

/// COB-ID of the LSS requests from the master (CiA 305 §7.2).
pub const LSS_REQUEST: u16 = 0x7E5;
/// COB-ID of the LSS answers of a slave.
pub const LSS_RESPONSE: u16 = 0x7E4;
/// The node-ID of a node that has none ("unconfigured", CiA 305 §6.1).
pub const UNCONFIGURED: u8 = 0xFF;

/// Command specifiers (CiA 305 §8, table 2).
pub mod cs {
    /// Switch state global.
    pub const SWITCH_GLOBAL: u8 = 0x04;
    /// Configure node-ID.
    pub const CONFIGURE_NODE_ID: u8 = 0x11;
    /// Configure bit timing parameters.
    pub const CONFIGURE_BIT_TIMING: u8 = 0x13;
    /// Activate bit timing parameters.
    pub const ACTIVATE_BIT_TIMING: u8 = 0x15;
    /// Store configuration.
    pub const STORE: u8 = 0x17;
    /// Switch state selective: vendor-ID, product code, revision number, serial number (0x40–0x43).
    pub const SELECTIVE_VENDOR: u8 = 0x40;
    /// Switch state selective: the slave's answer.
    pub const SELECTIVE_RESPONSE: u8 = 0x44;
    /// Identify remote slave: vendor-ID, product code, revision low/high, serial low/high (0x46–0x4B).
    pub const IDENTIFY_VENDOR: u8 = 0x46;
    /// Identify non-configured remote slave.
    pub const IDENTIFY_NON_CONFIGURED: u8 = 0x4C;
    /// Identify slave: the answer to the identify services and to Fastscan.
    pub const IDENTIFY_SLAVE: u8 = 0x4F;
    /// Identify non-configured slave: the answer.
    pub const IDENTIFY_NON_CONFIGURED_SLAVE: u8 = 0x50;
    /// Fastscan.
    pub const FASTSCAN: u8 = 0x51;
    /// Inquire identity vendor-ID, product code, revision number, serial number (0x5A–0x5D).
    pub const INQUIRE_VENDOR: u8 = 0x5A;
    /// Inquire node-ID.
    pub const INQUIRE_NODE_ID: u8 = 0x5E;
}

/// The LSS state of the slave (CiA 305 §6.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssState {
    /// LSS waiting: only switch state, identify and Fastscan are served.
    Waiting,
    /// LSS configuration: node-ID, bit timing, store and inquire are served.
    Configuration,
}

/// What the node has to do after a request.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LssAction {
    /// Nothing.
    None,
    /// The slave went back to waiting with a new node-ID while it had none: NMT reset communication
    /// with this node-ID now (CiA 305 §8.3.1).
    ApplyNodeId(u8),
    /// Store the pending node-ID and bit timing in non-volatile memory.
    Store {
        /// The pending node-ID (0xFF: none).
        node_id: u8,
        /// The pending bit-timing table index.
        bit_timing: u8,
    },
    /// Switch to the pending bit timing after the delay, in ms (CiA 305 §8.3.3).
    ActivateBitTiming {
        /// The table index.
        bit_timing: u8,
        /// The switch delay in ms.
        delay_ms: u16,
    },
}

/// The LSS address (CiA 305 §6.1): 0x1018 sub-indices 1 to 4.
pub type LssAddress = [u32; 4];

/// An LSS slave; see the [module documentation](self).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct LssSlave {
    address: LssAddress,
    state: LssState,
    /// The node-ID in use (0xFF: none).
    active: u8,
    /// The node-ID configured (active at the next reset communication).
    pending: u8,
    /// The bit-timing table index configured (CiA 301 table; 4 = 125 kbit/s).
    bit_timing: u8,
    /// Whether the node can keep a configuration (store answers "not supported" otherwise).
    can_store: bool,
    /// Switch state selective: how many parts of the address matched in sequence.
    selective: usize,
    /// Identify remote slave: the parts received (vendor, product, revision low/high, serial
    /// low/high).
    identify: [Option<u32>; 6],
    /// Fastscan: the part of the address under scan (0–3).
    fastscan_pos: u8,
}

impl LssSlave {
    /// A slave with `address` in the waiting state, its node-ID `node_id` (0xFF: none) active and
    /// pending, bit timing `bit_timing` (CiA 301 table index).
    pub fn new(address: LssAddress, node_id: u8, bit_timing: u8, can_store: bool) -> LssSlave {
        LssSlave {
            address,
            state: LssState::Waiting,
            active: node_id,
            pending: node_id,
            bit_timing,
            can_store,
            selective: 0,
            identify: [None; 6],
            fastscan_pos: 0,
        }
    }

    /// The LSS state.
    pub fn state(&self) -> LssState {
        self.state
    }

    /// The node-ID in use (0xFF: none).
    pub fn active_node_id(&self) -> u8 {
        self.active
    }

    /// The node-ID configured, active at the next NMT reset communication.
    pub fn pending_node_id(&self) -> u8 {
        self.pending
    }

    /// The bit-timing table index configured.
    pub fn bit_timing(&self) -> u8 {
        self.bit_timing
    }

    /// The LSS address.
    pub fn address(&self) -> LssAddress {
        self.address
    }

    /// The node has made the pending node-ID active (at its NMT reset communication).
    pub fn activate(&mut self) {
        self.active = self.pending;
    }

    /// Takes a request; returns the answer to send on [`LSS_RESPONSE`] and what the node has to do.
    pub fn handle(&mut self, data: &[u8]) -> (Option<[u8; 8]>, LssAction) {
        let Ok(data) = <[u8; 8]>::try_from(data) else {
            return (None, LssAction::None);
        };
        let command = data[0];
        let value = u32::from_le_bytes([data[1], data[2], data[3], data[4]]);
        let answer = |cs: u8, bytes: &[u8]| {
            let mut f = [0u8; 8];
            f[0] = cs;
            f[1..1 + bytes.len()].copy_from_slice(bytes);
            Some(f)
        };
        // A selective switch is a sequence of four requests with nothing between them (§8.2.2).
        if !(cs::SELECTIVE_VENDOR..=cs::SELECTIVE_VENDOR + 3).contains(&command) {
            self.selective = 0;
        }
        let configuring = self.state == LssState::Configuration;
        match command {
            cs::SWITCH_GLOBAL => return (None, self.switch_global(data[1])),
            c if (cs::SELECTIVE_VENDOR..=cs::SELECTIVE_VENDOR + 3).contains(&c) => {
                let part = usize::from(c - cs::SELECTIVE_VENDOR);
                if self.state != LssState::Waiting {
                    self.selective = 0;
                    return (None, LssAction::None);
                }
                // Each part must come in its turn and match; a mismatch starts the sequence over.
                self.selective = if part == self.selective && value == self.address[part] {
                    part + 1
                } else {
                    0
                };
                if self.selective == 4 {
                    self.selective = 0;
                    self.state = LssState::Configuration;
                    return (answer(cs::SELECTIVE_RESPONSE, &[]), LssAction::None);
                }
            }
            cs::CONFIGURE_NODE_ID if configuring => {
                let id = data[1];
                // Error 1: node-ID out of range (§8.3.1).
                let error = if (1..=127).contains(&id) || id == UNCONFIGURED {
                    self.pending = id;
                    0
                } else {
                    1
                };
                return (answer(command, &[error]), LssAction::None);
            }
            cs::CONFIGURE_BIT_TIMING if configuring => {
                let (table, index) = (data[1], data[2]);
                let error = if table == 0 && matches!(index, 0..=4 | 6..=8) {
                    self.bit_timing = index;
                    0
                } else {
                    1
                };
                return (answer(command, &[error]), LssAction::None);
            }
            cs::ACTIVATE_BIT_TIMING if configuring => {
                let delay_ms = u16::from_le_bytes([data[1], data[2]]);
                return (
                    None,
                    LssAction::ActivateBitTiming {
                        bit_timing: self.bit_timing,
                        delay_ms,
                    },
                );
            }
            cs::STORE if configuring => {
                if !self.can_store {
                    return (answer(command, &[1]), LssAction::None);
                }
                return (
                    answer(command, &[0]),
                    LssAction::Store {
                        node_id: self.pending,
                        bit_timing: self.bit_timing,
                    },
                );
            }
            c if configuring && (cs::INQUIRE_VENDOR..=cs::INQUIRE_VENDOR + 3).contains(&c) => {
                let part = usize::from(c - cs::INQUIRE_VENDOR);
                return (
                    answer(c, &self.address[part].to_le_bytes()),
                    LssAction::None,
                );
            }
            cs::INQUIRE_NODE_ID if configuring => {
                return (answer(command, &[self.active]), LssAction::None);
            }
            c if (cs::IDENTIFY_VENDOR..cs::IDENTIFY_VENDOR + 6).contains(&c) => {
                let part = usize::from(c - cs::IDENTIFY_VENDOR);
                self.identify[part] = Some(value);
                if part == 5 {
                    let received = std::mem::take(&mut self.identify);
                    if self.identified(received) {
                        return (answer(cs::IDENTIFY_SLAVE, &[]), LssAction::None);
                    }
                }
            }
            cs::IDENTIFY_NON_CONFIGURED if self.active == UNCONFIGURED => {
                return (
                    answer(cs::IDENTIFY_NON_CONFIGURED_SLAVE, &[]),
                    LssAction::None,
                );
            }
            cs::FASTSCAN if self.fastscan(value, data[5], data[6], data[7]) => {
                return (answer(cs::IDENTIFY_SLAVE, &[]), LssAction::None);
            }
            _ => {}
        }
        (None, LssAction::None)
    }

    /// Switch state global (§8.2.1): 0 waiting, 1 configuration; another mode is ignored.
    fn switch_global(&mut self, mode: u8) -> LssAction {
        match mode {
            0 => {
                let was = self.state;
                self.state = LssState::Waiting;
                if was == LssState::Configuration
                    && self.active == UNCONFIGURED
                    && self.pending != UNCONFIGURED
                {
                    return LssAction::ApplyNodeId(self.pending);
                }
            }
            1 => self.state = LssState::Configuration,
            _ => {}
        }
        LssAction::None
    }

    /// Identify remote slave (§8.4.2): vendor-ID and product code equal, revision and serial number
    /// within the ranges, all six parts received.
    fn identified(&self, parts: [Option<u32>; 6]) -> bool {
        let [Some(vendor), Some(product), Some(rev_low), Some(rev_high), Some(serial_low), Some(serial_high)] =
            parts
        else {
            return false;
        };
        let [v, p, r, s] = self.address;
        v == vendor
            && p == product
            && (rev_low..=rev_high).contains(&r)
            && (serial_low..=serial_high).contains(&s)
    }

    /// Fastscan (§8.4.4): `bit_checked` 0x80 asks every non-configured slave to answer and starts a
    /// scan; otherwise the slave answers when the bits of `id_number` from `bit_checked` up match the
    /// part `sub` of its address it is at. A match of the whole part (`bit_checked` 0) moves on to
    /// part `next`; the last one (next back below sub) puts the slave into the configuration state.
    fn fastscan(&mut self, id_number: u32, bit_checked: u8, sub: u8, next: u8) -> bool {
        if self.active != UNCONFIGURED || self.state != LssState::Waiting {
            return false;
        }
        if bit_checked == 0x80 {
            self.fastscan_pos = 0;
            return true;
        }
        // The position is 0–3 (only ever set from a `next` checked here), so `sub` is too after this.
        if bit_checked > 31 || next > 3 || sub != self.fastscan_pos {
            return false;
        }
        let mask = u32::MAX << bit_checked;
        if (id_number ^ self.address[usize::from(sub)]) & mask != 0 {
            return false;
        }
        if bit_checked == 0 {
            if next < sub {
                self.state = LssState::Configuration;
                self.fastscan_pos = 0;
            } else {
                self.fastscan_pos = next;
            }
        }
        true
    }
}
