//! The SDO client on a CAN bus: one node's SDO channel ([`BusTransport`]), when block transfer is
//! used ([`BlockMode`]), and [`CanSdo`], the [`SdoAccess`] of CANopen.

use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Instant;

use od::abort::AbortCode;
use od::dict::Address;
use od::sdo::client::{ClientConfig, SdoClientError};
use od::sdo::frame::Frame;
use od::sdo::session::{SdoSession, SdoTransport, SessionError};
use od::types::DataType;
use od::value::Value;

use crate::link::{BusError, BusEvent, CanBus, CanFrame};
use crate::{SdoAccess, ToolError, UsageError};

/// One node's SDO channel on a bus.
pub struct BusTransport<'a> {
    bus: &'a mut dyn CanBus,
    node: u8,
}

impl<'a> BusTransport<'a> {
    /// The channel to `node` on `bus`.
    pub fn new(bus: &'a mut dyn CanBus, node: u8) -> BusTransport<'a> {
        BusTransport { bus, node }
    }
}

impl SdoTransport for BusTransport<'_> {
    type Error = BusError;

    fn send(&mut self, frame: &Frame) -> Result<(), BusError> {
        // 8 bytes to 0x600 + 1…127 always make a CAN frame.
        let f = CanFrame::new(0x600 + u16::from(self.node), frame).ok_or_else(|| {
            BusError::Protocol {
                what: self.bus.describe(),
                detail: format!("no SDO request COB-ID for node {}", self.node),
            }
        })?;
        self.bus.send(&f)
    }

    fn recv(&mut self, until: Instant) -> Result<Option<Frame>, BusError> {
        let want = 0x580 + u16::from(self.node);
        loop {
            let left = until.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(None);
            }
            match self.bus.recv(left) {
                Ok(Some(BusEvent::Frame { frame, .. }))
                    if frame.cob_id() == Some(want) && frame.len() == 8 && !frame.is_rtr() =>
                {
                    return Ok(Some(frame.data8()));
                }
                Ok(Some(_)) => {}
                Ok(None) => return Ok(None),
                Err(e) => return Err(e),
            }
        }
    }

    fn now(&self) -> Instant {
        Instant::now()
    }
}

/// The size from which a transfer is large enough for SDO block transfer in [`BlockMode::Auto`]:
/// a download of more than 64 bytes goes by block, and a block upload lets the server answer an
/// entry of at most 64 bytes with a normal upload (CiA 301 §7.2.4.3.13, the protocol switch
/// threshold).
pub const BLOCK_FROM: usize = 64;

/// When the tool uses SDO block transfer (CiA 301 §7.2.4.3.9–16).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlockMode {
    /// Block transfer for what is known to be large, expedited or segmented transfer for the rest
    /// (as python-canopen, whose block transfer is asked for by `block_transfer=True`, and
    /// CANopenNode's gateway, `set sdo_block 0` by default, do): a download of more than
    /// [`BLOCK_FROM`] bytes, and an upload of an entry the description makes a DOMAIN or of one
    /// `upload` moves into a file, offering the server the switch to a normal upload up to
    /// [`BLOCK_FROM`] bytes. A read of 4 bytes is one expedited request and its answer.
    #[default]
    Auto,
    /// `--block`: every upload whose size is not known to fit 4 bytes and every download of more
    /// than 4 bytes by block transfer.
    Always,
    /// `--no-block`: expedited and segmented transfers only.
    Never,
}

/// A transfer about to start, as [`BlockMode`] sees it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Transfer {
    /// An upload; `domain`: the description makes the entry a DOMAIN.
    Upload { domain: bool },
    /// A download: block transfer when its data is larger than the client's threshold.
    Download,
}

impl BlockMode {
    /// `base` with block transfer on or off for `transfer`.
    fn config(self, base: &ClientConfig, transfer: Transfer) -> ClientConfig {
        let mut config = base.clone();
        match self {
            BlockMode::Always => config.block = true,
            BlockMode::Never => config.block = false,
            BlockMode::Auto => {
                // A download goes by block only above the threshold (the client's rule).
                config.block = match transfer {
                    Transfer::Upload { domain } => domain,
                    Transfer::Download => true,
                };
                config.block_threshold = BLOCK_FROM;
                config.pst = BLOCK_FROM as u8;
            }
        }
        config
    }
}

/// The SDO client on a CAN bus, with its settings: [`SdoAccess`] over CANopen.
pub struct CanSdo<'a> {
    /// The bus.
    pub bus: &'a mut dyn CanBus,
    /// The client settings (timeout; block transfer as [`CanSdo::block`] says).
    pub config: &'a ClientConfig,
    /// When block transfer is used.
    pub block: BlockMode,
    /// Set (by a Ctrl-C handler) to abort the running transfer.
    pub cancel: Option<Arc<AtomicBool>>,
}

impl<'a> CanSdo<'a> {
    /// The SDO client on `bus` with `config`, block transfer in [`BlockMode::Auto`].
    pub fn new(bus: &'a mut dyn CanBus, config: &'a ClientConfig) -> CanSdo<'a> {
        CanSdo {
            bus,
            config,
            block: BlockMode::Auto,
            cancel: None,
        }
    }

    fn session_error(&self, node: u8, addr: Address, e: SessionError<BusError>) -> ToolError {
        match e {
            SessionError::Sdo(SdoClientError::Aborted {
                code: AbortCode::Timeout,
                ..
            }) => ToolError::Timeout {
                index: addr.index,
                sub: addr.sub,
                node,
                ms: self.config.timeout.as_millis(),
            },
            SessionError::Sdo(SdoClientError::Aborted {
                index, sub, code, ..
            }) => ToolError::Abort { index, sub, code },
            SessionError::Transport(e) => ToolError::Bus(e),
            SessionError::Cancelled => ToolError::Interrupted { removed: None },
            other => ToolError::Session(other),
        }
    }

    /// Runs `transfer` through a session on `node`, mapping its errors.
    pub(crate) fn transfer<R>(
        &mut self,
        node: u8,
        addr: Address,
        transfer: Transfer,
        f: impl FnOnce(&mut SdoSession<BusTransport<'_>>) -> Result<R, SessionError<BusError>>,
    ) -> Result<R, ToolError> {
        self.check_node(node)?;
        let config = self.block.config(self.config, transfer);
        let mut session = SdoSession::new(BusTransport::new(&mut *self.bus, node), config);
        if let Some(flag) = &self.cancel {
            session = session.with_cancel(Arc::clone(flag));
        }
        let result = f(&mut session);
        drop(session);
        result.map_err(|e| self.session_error(node, addr, e))
    }
}

impl SdoAccess for CanSdo<'_> {
    fn check_node(&self, node: u8) -> Result<(), ToolError> {
        if (1..=127).contains(&node) {
            Ok(())
        } else {
            Err(UsageError::Node { node }.into())
        }
    }

    fn read_bytes(&mut self, node: u8, addr: Address) -> Result<Vec<u8>, ToolError> {
        let mux = Address::new(addr.index, addr.sub);
        let upload = Transfer::Upload { domain: false };
        self.transfer(node, addr, upload, |s| s.read_bytes(mux))
    }

    fn write_bytes(&mut self, node: u8, addr: Address, data: &[u8]) -> Result<(), ToolError> {
        let mux = Address::new(addr.index, addr.sub);
        self.transfer(node, addr, Transfer::Download, |s| s.write_bytes(mux, data))
    }

    /// The size of a fixed-size type keeps small values out of block mode; a DOMAIN is large.
    fn read_value(
        &mut self,
        node: u8,
        addr: Address,
        data_type: DataType,
    ) -> Result<Value, ToolError> {
        let mux = Address::new(addr.index, addr.sub);
        let upload = Transfer::Upload {
            domain: data_type == DataType::Domain,
        };
        self.transfer(node, addr, upload, |s| s.read_value(mux, data_type))
    }
}
