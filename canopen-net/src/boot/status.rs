//! The CiA 302-2 error status of the boot-slave process and the events of the manager.

use std::fmt;

/// The error status of CiA 302-2's boot-slave process (§4, figures 5 to 11): the letter a failed
/// step ends with, and a lost node's error control event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ErrorStatus {
    /// A: the node is no slave in 0x1F81.
    A,
    /// B: no answer to the upload of 0x1000.
    B,
    /// C: 0x1000 differs from 0x1F84.
    C,
    /// D: 0x1018:01 differs from 0x1F85.
    D,
    /// E: heartbeat event, no heartbeat in the consumer time.
    E,
    /// F: node guarding event.
    F,
    /// G: the software version is to be checked, and the objects for it are not configured.
    G,
    /// H: a software update is needed and not allowed.
    H,
    /// I: a software update is needed and the program download failed.
    I,
    /// J: the configuration download failed.
    J,
    /// K: no heartbeat while error control started.
    K,
    /// L: the slave was operational already (kept alive, not booted again).
    L,
    /// M: 0x1018:02 differs from 0x1F86.
    M,
    /// N: 0x1018:03 differs from 0x1F87.
    N,
    /// O: 0x1018:04 differs from 0x1F88.
    O,
}

impl ErrorStatus {
    /// The letter.
    pub fn letter(self) -> char {
        use ErrorStatus::*;
        match self {
            A => 'A',
            B => 'B',
            C => 'C',
            D => 'D',
            E => 'E',
            F => 'F',
            G => 'G',
            H => 'H',
            I => 'I',
            J => 'J',
            K => 'K',
            L => 'L',
            M => 'M',
            N => 'N',
            O => 'O',
        }
    }

    /// What CiA 302-2 says the letter means.
    pub fn meaning(self) -> &'static str {
        use ErrorStatus::*;
        match self {
            A => "the node is no slave in 0x1F81",
            B => "no answer to the upload of 0x1000",
            C => "device type 0x1000 differs from 0x1F84",
            D => "vendor-ID 0x1018:01 differs from 0x1F85",
            E => "heartbeat event: no heartbeat in the consumer time",
            F => "node guarding event: no answer to node guarding",
            G => "the objects for the software version check are not configured",
            H => "a software update is needed and not allowed",
            I => "a software update is needed and the program download failed",
            J => "the configuration download failed",
            K => "no heartbeat while error control started",
            L => "the slave was operational already",
            M => "product code 0x1018:02 differs from 0x1F86",
            N => "revision number 0x1018:03 differs from 0x1F87",
            O => "serial number 0x1018:04 differs from 0x1F88",
        }
    }
}

/// Why one node did not boot or was lost: the CiA 302-2 letter and one line in words naming the
/// object, the expected and the found value and where the expected value comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BootError {
    /// The node-ID.
    pub node: u8,
    /// The error status.
    pub status: ErrorStatus,
    /// What happened, in words.
    pub message: String,
}

impl fmt::Display for BootError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "node {} [{}] {}",
            self.node,
            self.status.letter(),
            self.message
        )
    }
}

impl std::error::Error for BootError {}

/// Where a node is in its boot.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum NodeState {
    /// Waiting for its boot-up message after the master's reset.
    Resetting,
    /// Its identity being checked.
    Checking,
    /// Its configuration being written: entries written so far of all.
    Configuring {
        /// Entries written.
        done: usize,
        /// All entries.
        of: usize,
    },
    /// Waiting for its first heartbeat.
    ErrorControl,
    /// Booted: configured, and started unless the master starts no slave; supervised.
    Up,
    /// Watched only: 0x1F81 bit 2 clear, the master neither configures nor starts it.
    Watched,
    /// Its boot failed or it was lost; booted again at its next boot-up message (or heartbeat
    /// after a loss), and after [`crate::boot::RETRY`] when it did not answer.
    Failed(BootError),
}

impl NodeState {
    /// A short word for a table: `reset`, `checking`, `config 3/7`, `heartbeat`, `up`, `watched`,
    /// `failed`.
    pub fn word(&self) -> String {
        match self {
            NodeState::Resetting => "reset".into(),
            NodeState::Checking => "checking".into(),
            NodeState::Configuring { done, of } => format!("config {done}/{of}"),
            NodeState::ErrorControl => "heartbeat".into(),
            NodeState::Up => "up".into(),
            NodeState::Watched => "watched".into(),
            NodeState::Failed(e) => format!("failed {}", e.status.letter()),
        }
    }
}

/// What the manager reports, taken with [`crate::boot::Manager::poll_event`].
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BootEvent {
    /// A node's state changed (its configuration's progress is not an event: it is in its
    /// [`crate::boot::NodeReport`]).
    Node {
        /// The node-ID.
        node: u8,
        /// Its new state.
        state: NodeState,
    },
    /// Every mandatory slave booted: the slaves were started (all at once when 0x1F80 bit 1 says
    /// so) and the master entered Operational unless 0x1F80 bit 2 says not to.
    NetworkUp,
    /// The boot time 0x1F89 passed with these mandatory slaves not booted: the network does not
    /// come up (the manager goes on trying them).
    BootTimeout {
        /// The mandatory slaves not booted.
        missing: Vec<u8>,
    },
    /// A node sent an emergency message (CiA 301 §7.2.7).
    Emergency {
        /// The node-ID.
        node: u8,
        /// The error code.
        code: u16,
        /// The error register (0x1001).
        register: u8,
        /// The manufacturer-specific bytes.
        data: [u8; 5],
    },
    /// The master sent an NMT command (CiA 301 §7.2.8.3.1) to a node (0: all).
    Nmt {
        /// The command specifier.
        command: u8,
        /// The node-ID, 0 for all.
        node: u8,
    },
}
