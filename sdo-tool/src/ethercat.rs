//! `sdo-tool --ethercat IFACE`: the SDO commands over EtherCAT, through the CoE mailboxes of the
//! slaves, with ethercrab as the master.
//!
//! [`EthercatSession::open`] opens the interface with a raw socket (`ecat-link`'s, with ethercrab's
//! frames sent and received over it by a TX/RX task of this module's; with a capture, every frame
//! goes to it too) and first reads the slaves' AL status with one broadcast read. A chain beyond Init belongs to another master (or a
//! configuration tool): the session refuses it, naming the state, and sends nothing else — it never
//! changes the state of a running chain. A chain in Init is brought to Pre-Op (mailboxes configured
//! from each slave's SII) for the transfers; NODE is the slave's position in the chain, 1 for the
//! first. Each transfer runs the TX/RX task and the transfer in one executor
//! (`async_io::block_on`) until the transfer ends; between transfers nothing is sent. Dropping the
//! session asks every slave for Init again (the state it found) and closes the socket.
//!
//! - **Upload**: ethercrab's `sdo_read` into a byte buffer (expedited, normal and segmented upload).
//! - **Download**: 1 to 4 bytes with ethercrab's `sdo_write` of the byte slice (expedited); other
//!   lengths — ethercrab has no normal download — as a normal download (ETG.1000.6 §5.6.2.1, the
//!   data in the initiate request) that this module puts into the slave's write mailbox (SM0) and
//!   whose answer it takes from the read mailbox (SM1) itself, with mailbox counter 0 (no repeat
//!   detection, so ethercrab's own counter sequence is not disturbed). The data must fit one mailbox.
//! - **FoE** (`foe`): files to and from a slave through the same mailboxes (ethercrab has no FoE),
//!   in Bootstrap where asked.
//! - A frame has as long to come back as a mailbox answer (the session's timeout, 100 ms at least).
//! - An SDO abort is [`ToolError::Abort`] with the code (and its CiA 301 meaning) as over CAN; no
//!   answer within the timeout is [`ToolError::Timeout`]; anything else of the network is
//!   [`ToolError::Ethercat`].
//!
//! The session's PDU storage is allocated once per session and not freed (ethercrab borrows it for
//! the life of the master; about 18 KB).
//!
//! [`Chain`] looks at a chain without a session, one datagram at a time, in any state and whoever
//! runs it: AL states, registers and the SII (the commands of IgH's tool).

use std::future::Future;
use std::pin::Pin;
use std::time::{Duration, Instant};

use ethercrab::error::{Error, MailboxError};
use ethercrab::std::ethercat_now;
use ethercrab::{
    Command, MainDevice, MainDeviceConfig, PduRx, PduStorage, PduTx, SubDeviceGroup, Timeouts,
};
use futures_lite::future;
use od::abort::AbortCode;
use od::coe::info;
use od::coe::mailbox::{CoeHeader, MailboxHeader, MailboxType};
use od::coe::sdo::{CoeSdo, CoeSdoCommand};
use od::dict::Address;
use od::sdo::frame::{ClientFrame, ServerFrame};
use od::types::DataType;

use crate::{SdoAccess, ToolError};

mod chain;
mod foe;
mod mailbox;
mod op;
mod txrx;
pub use chain::{state_name, states, Chain, SiiRead, SlaveInfo, MAX_DATAGRAM, PROBE_INDEX};
pub use foe::{FoeFailure, MAX_FOE_READ};
use mailbox::exchange as mailbox_exchange;
pub use op::OpSession;

use crate::link::Capture;

/// Slaves a chain may have here (ethercrab wants a power of two).
pub const MAX_SLAVES: usize = 128;
/// The group's process data image, for a command that runs the chain in Op.
const MAX_PDI: usize = 1024;
/// Frames in flight at most.
const MAX_FRAMES: usize = 16;
/// The data of one PDU at most: a mailbox of up to 1,100 bytes.
const MAX_PDU_DATA: usize = PduStorage::element_size(1100);
/// The largest entry an upload reads.
pub const MAX_UPLOAD: usize = 4096;
/// AL control and AL status (ETG.1000.4 §6.4.1).
const AL_CONTROL: u16 = 0x0120;
const AL_STATUS: u16 = 0x0130;
/// AL state Init.
const INIT: u16 = 0x01;

/// The state a broadcast read of AL status shows beyond Init (`al` is every slave's status OR'd):
/// the highest one, or `None` when every slave is in Init.
pub fn beyond_init(al: u16) -> Option<&'static str> {
    let states = al & 0x0F;
    if states & 0x08 != 0 {
        Some("Op")
    } else if states & 0x04 != 0 {
        Some("Safe-Op")
    } else if states == 0x03 {
        Some("Bootstrap")
    } else if states & 0x02 != 0 {
        Some("Pre-Op")
    } else {
        None
    }
}

type TxRx = Pin<Box<dyn Future<Output = Result<(PduTx<'static>, PduRx<'static>), Error>>>>;
type Group = SubDeviceGroup<MAX_SLAVES, MAX_PDI>;

/// Why a transfer failed, before it is told in the tool's words.
enum Failure {
    /// ethercrab's error.
    Master(Error),
    /// The slave aborted the transfer.
    Abort(u32),
    /// No answer in time.
    Timeout,
    /// The slave's answer is not what the protocol says, or the data does not fit.
    Protocol(String),
    /// The slave answered with a mailbox error (ETG.1000.4 Table 30: 2 unsupported protocol, …).
    MailboxError(u16),
    /// A request longer than the slave's write mailbox.
    TooLong {
        /// The request's bytes.
        bytes: usize,
        /// The mailbox's.
        mailbox: u16,
    },
}

impl From<Error> for Failure {
    fn from(e: Error) -> Failure {
        match e {
            Error::Mailbox(MailboxError::Aborted { code, .. }) => Failure::Abort(u32::from(code)),
            Error::Timeout(_) => Failure::Timeout,
            other => Failure::Master(other),
        }
    }
}

/// An EtherCAT chain in Pre-Op, for SDO transfers to its slaves.
pub struct EthercatSession {
    link: Link,
    group: Box<Group>,
}

/// The master on one interface, whatever state its chain is in.
struct Link {
    interface: String,
    maindevice: MainDevice<'static>,
    /// The TX/RX task of ethercrab's frames; `None` once it ended (the socket failed).
    tx_rx: Option<TxRx>,
    timeout: Duration,
}

/// The TX/RX task ended (it stops at the first frame ethercrab cannot place, e.g. one of another
/// master that reached its socket before the socket was bound to the interface): its error, or none
/// when it ended without one.
#[derive(Debug)]
pub struct TaskEnded(Option<Error>);

impl std::fmt::Display for TaskEnded {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0 {
            Some(e) => write!(f, "the TX/RX task failed: {e}"),
            None => f.write_str("the TX/RX task has ended"),
        }
    }
}

impl std::error::Error for TaskEnded {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.as_ref().map(|e| e as _)
    }
}

/// Longest network interface name Linux takes (IFNAMSIZ less the terminating NUL).
pub const MAX_INTERFACE_NAME: usize = 15;

/// Checks that `name` can name a network interface: 1 to 15 bytes, no `/`, whitespace or NUL, not
/// `.` or `..` (the kernel's rules), before any socket is opened.
pub fn check_interface_name(name: &str) -> Result<(), EthercatError> {
    let bad = name.is_empty()
        || name.len() > MAX_INTERFACE_NAME
        || name == "."
        || name == ".."
        || name
            .chars()
            .any(|c| c == '/' || c == '\0' || c.is_whitespace());
    if bad {
        return Err(EthercatError::InterfaceName {
            interface: name.escape_debug().to_string(),
        });
    }
    Ok(())
}

/// Why the EtherCAT side of the tool failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum EthercatError {
    /// The name cannot name a network interface.
    #[error(
        "interface \"{interface}\": not an interface name (1 to {MAX_INTERFACE_NAME} bytes, no '/', space or NUL)"
    )]
    InterfaceName {
        /// The name given, escaped.
        interface: String,
    },
    /// The chain did not reach Op for a command that runs it.
    #[error("interface {interface}: the chain did not reach Op: {detail}")]
    Op {
        /// The interface.
        interface: String,
        /// What ethercrab or the slaves said.
        detail: String,
    },
    /// ethercrab's frame storage is taken (one session per process).
    #[error("the PDU storage is in use")]
    Storage,
    /// No network interface has the name.
    #[error("no such network interface: {interface}")]
    NoInterface {
        /// The name given.
        interface: String,
    },
    /// A slave did not answer a datagram addressed to it.
    #[error("interface {interface}: slave {position} did not answer {what}")]
    NoAnswer {
        /// The interface.
        interface: String,
        /// The slave's position (1 = first).
        position: u16,
        /// The datagram.
        what: String,
    },
    /// A slave's EEPROM interface refused a command or stayed busy.
    #[error("interface {interface}: the EEPROM of slave {position}: {detail}")]
    Eeprom {
        /// The interface.
        interface: String,
        /// The slave's position (1 = first).
        position: u16,
        /// What went wrong.
        detail: String,
    },
    /// The interface could not be opened.
    #[error("interface {interface}: {source}")]
    Interface {
        /// The interface.
        interface: String,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The chain is beyond Init: another master (or a configuration tool) has it.
    #[error("interface {interface}: the chain is in {state} (AL status 0x{al:04X}, every slave's OR'd): another master runs it; sdo-tool --ethercat takes only a chain in Init and leaves it there")]
    Running {
        /// The interface.
        interface: String,
        /// The highest state found.
        state: &'static str,
        /// The AL status read.
        al: u16,
    },
    /// The slaves could not be initialised.
    #[error("interface {interface}: the slaves could not be brought to Pre-Op: {source}")]
    Init {
        /// The interface.
        interface: String,
        /// ethercrab's reason.
        source: Error,
    },
    /// The TX/RX task ended on every try while the slaves were initialised.
    #[error("interface {interface}: the slaves could not be brought to Pre-Op: {source}")]
    InitEnded {
        /// The interface.
        interface: String,
        /// How the task ended the last time.
        source: TaskEnded,
    },
    /// No slave answered.
    #[error("interface {interface}: no EtherCAT slave answered")]
    NoSlaves {
        /// The interface.
        interface: String,
    },
    /// The TX/RX task ended during a transfer.
    #[error("interface {interface}: {source}")]
    Ended {
        /// The interface.
        interface: String,
        /// How it ended.
        source: TaskEnded,
    },
    /// A transfer failed in ethercrab.
    #[error("{addr} of slave {position}: {source}")]
    Transfer {
        /// The entry.
        addr: Address,
        /// The slave's position.
        position: u8,
        /// ethercrab's reason.
        source: Error,
    },
    /// The slave's answer is not what the protocol says, or the data does not fit.
    #[error("{addr} of slave {position}: {detail}")]
    Protocol {
        /// The entry.
        addr: Address,
        /// The slave's position.
        position: u8,
        /// What was wrong.
        detail: String,
    },
}

/// Runs `f` with the TX/RX task until `f` ends; the task's end is an error (and `tx_rx` is `None`
/// then).
fn drive<T>(tx_rx: &mut Option<TxRx>, f: impl Future<Output = T>) -> Result<T, TaskEnded> {
    let Some(task) = tx_rx.as_mut() else {
        return Err(TaskEnded(None));
    };
    let mut ended = None;
    let r = async_io::block_on(future::or(async { Some(f.await) }, async {
        let r = task.as_mut().await;
        ended = Some(r.err());
        None
    }));
    match r {
        Some(v) => Ok(v),
        None => {
            *tx_rx = None;
            Err(TaskEnded(ended.flatten()))
        }
    }
}

impl Drop for Link {
    /// Every slave back to Init, the state the session found the chain in (from Pre-Op, or from Op
    /// after a command that ran the chain): one broadcast write of AL control, then AL status read
    /// until every slave shows Init (at most the session's timeout).
    fn drop(&mut self) {
        let md = &self.maindevice;
        let asked = drive(
            &mut self.tx_rx,
            Command::bwr(AL_CONTROL).ignore_wkc().send(md, INIT),
        );
        if !matches!(asked, Ok(Ok(()))) {
            return;
        }
        let deadline = Instant::now() + self.timeout;
        while Instant::now() < deadline {
            let al = drive(
                &mut self.tx_rx,
                Command::brd(AL_STATUS).ignore_wkc().receive::<u16>(md),
            );
            match al {
                Ok(Ok(al)) if beyond_init(al).is_none() => return,
                Ok(Ok(_)) => std::thread::sleep(Duration::from_millis(1)),
                _ => return,
            }
        }
    }
}

/// Why opening failed.
enum OpenError {
    /// The TX/RX task ended while the slaves were initialised: worth another try.
    TaskEnded(TaskEnded),
    /// Anything else.
    Tool(Box<ToolError>),
}

impl OpenError {
    fn tool(e: impl Into<ToolError>) -> OpenError {
        OpenError::Tool(Box::new(e.into()))
    }
}

impl EthercatSession {
    /// Opens `interface`, finds the slaves and brings them to Pre-Op; `timeout` is how long a slave
    /// has to answer a mailbox request.
    ///
    /// A raw socket takes EtherCAT frames of every interface until it is bound to this one, and the
    /// TX/RX task ends at the first frame ethercrab cannot place: with another master busy on
    /// another interface, a stray frame may end the first try. Up to three tries are made.
    pub fn open(interface: &str, timeout: Duration) -> Result<EthercatSession, ToolError> {
        EthercatSession::open_captured(interface, timeout, None)
    }

    /// [`EthercatSession::open`], every frame of the session written to `capture` too.
    pub fn open_captured(
        interface: &str,
        timeout: Duration,
        capture: Option<&Capture>,
    ) -> Result<EthercatSession, ToolError> {
        check_interface_name(interface)?;
        let mut last = TaskEnded(None);
        for _ in 0..3 {
            match EthercatSession::try_open(interface, timeout, capture) {
                Ok(s) => return Ok(s),
                Err(OpenError::Tool(e)) => return Err(*e),
                Err(OpenError::TaskEnded(why)) => last = why,
            }
        }
        Err(EthercatError::InitEnded {
            interface: interface.to_string(),
            source: last,
        }
        .into())
    }

    fn try_open(
        interface: &str,
        timeout: Duration,
        capture: Option<&Capture>,
    ) -> Result<EthercatSession, OpenError> {
        // Before ethercrab sends anything: a chain another master runs is left alone.
        let al = chain::al_status(interface, capture).map_err(OpenError::tool)?;
        if let Some(al) = al {
            if let Some(state) = beyond_init(al) {
                return Err(OpenError::tool(EthercatError::Running {
                    interface: interface.to_string(),
                    state,
                    al,
                }));
            }
        }
        let storage: &'static PduStorage<MAX_FRAMES, MAX_PDU_DATA> =
            Box::leak(Box::new(PduStorage::new()));
        let (tx, rx, pdu_loop) = storage
            .try_split()
            .map_err(|_| OpenError::tool(EthercatError::Storage))?;
        let maindevice = MainDevice::new(
            pdu_loop,
            Timeouts {
                // The answer's timeout (--timeout-ms, at least 100 ms), for a frame and an EEPROM
                // read too: on a link that loses no frame, an answer late on a loaded machine (the
                // tool or the slaves descheduled) is still an answer, and a frame that comes back
                // after its timeout ends ethercrab's TX/RX task. An FoE transfer of a megabyte is
                // tens of thousands of frames: one late frame must not end it.
                pdu: timeout.max(Duration::from_millis(100)),
                eeprom: timeout.max(Duration::from_millis(100)),
                wait_loop_delay: Duration::from_millis(1),
                mailbox_response: timeout,
                ..Timeouts::default()
            },
            MainDeviceConfig {
                // The slaves stay in Pre-Op: no clock to synchronise.
                dc_static_sync_iterations: 0,
                ..MainDeviceConfig::default()
            },
        );
        let socket = chain::open_socket(interface, capture).map_err(OpenError::tool)?;
        let task = txrx::TxRx::new(socket, tx, rx).map_err(|source| {
            OpenError::tool(EthercatError::Interface {
                interface: interface.to_string(),
                source,
            })
        })?;
        let mut tx_rx: Option<TxRx> = Some(Box::pin(task));
        let group = drive(
            &mut tx_rx,
            maindevice.init_single_group::<MAX_SLAVES, MAX_PDI>(ethercat_now),
        )
        .map_err(OpenError::TaskEnded)?
        .map_err(|source| {
            OpenError::tool(EthercatError::Init {
                interface: interface.to_string(),
                source,
            })
        })?;
        if group.is_empty() {
            return Err(OpenError::tool(EthercatError::NoSlaves {
                interface: interface.to_string(),
            }));
        }
        Ok(EthercatSession {
            link: Link {
                interface: interface.to_string(),
                maindevice,
                tx_rx,
                timeout,
            },
            group: Box::new(group),
        })
    }
}

impl Link {
    /// The tool's error for the end of the TX/RX task.
    fn ended(&self, source: TaskEnded) -> ToolError {
        EthercatError::Ended {
            interface: self.interface.clone(),
            source,
        }
        .into()
    }

    /// The tool's error for a failed transfer to `addr` on the slave at `position`.
    fn error(&self, position: u8, addr: Address, f: Failure) -> ToolError {
        match f {
            Failure::Abort(code) => ToolError::Abort {
                index: addr.index,
                sub: addr.sub,
                code: AbortCode::from(code),
            },
            Failure::Timeout => ToolError::Timeout {
                index: addr.index,
                sub: addr.sub,
                node: position,
                ms: self.timeout.as_millis(),
            },
            Failure::Master(source) => EthercatError::Transfer {
                addr,
                position,
                source,
            }
            .into(),
            Failure::Protocol(detail) => EthercatError::Protocol {
                addr,
                position,
                detail,
            }
            .into(),
            Failure::MailboxError(code) => EthercatError::Protocol {
                addr,
                position,
                detail: format!(
                    "the slave answered with mailbox error {code} ({})",
                    mailbox_error(code)
                ),
            }
            .into(),
            Failure::TooLong { bytes, mailbox } => EthercatError::Protocol {
                addr,
                position,
                detail: format!(
                    "a {bytes}-byte request does not fit the slave's {mailbox}-byte mailbox"
                ),
            }
            .into(),
        }
    }
}

/// The meaning of a mailbox error code (ETG.1000.4 §5.6, the error reply's Detail).
pub fn mailbox_error(code: u16) -> &'static str {
    match code {
        1 => "syntax of the mailbox header",
        2 => "mailbox protocol not supported",
        3 => "channel field invalid",
        4 => "service not supported",
        5 => "invalid mailbox header",
        6 => "mailbox data too short",
        7 => "no more memory in the slave",
        8 => "inconsistent data length",
        _ => "unknown code",
    }
}

/// A normal download of `data` to `mux` on the slave at `station` (ETG.1000.6 §5.6.2.1, the data
/// in the initiate request).
async fn normal_download(
    maindevice: &MainDevice<'_>,
    station: u16,
    mux: Address,
    data: &[u8],
    timeout: Duration,
) -> Result<(), Failure> {
    let size = u32::try_from(data.len())
        .map_err(|_| Failure::Protocol(format!("{} bytes are too many", data.len())))?;
    let request = CoeSdo {
        command: CoeSdoCommand::Request(ClientFrame::InitiateDownloadSegmented {
            mux,
            size: Some(size),
        }),
        complete_access: false,
        extra: data,
    }
    .to_mailbox(0, 0);
    let mut done = Err(Failure::Timeout);
    mailbox_exchange(maindevice, station, request, timeout, |body| {
        let sdo = CoeHeader::parse(body)
            .map_err(|e| e.to_string())
            .and_then(|h| CoeSdo::parse(h.service, &body[2..]).map_err(|e| e.to_string()))
            .map_err(|e| {
                Failure::Protocol(format!("the slave's answer is no CoE SDO response: {e}"))
            })?;
        done = match sdo.command {
            CoeSdoCommand::Response(ServerFrame::InitiateDownload { mux: m }) if m == mux => Ok(()),
            CoeSdoCommand::Request(ClientFrame::Abort { code, .. })
            | CoeSdoCommand::Response(ServerFrame::Abort { code, .. }) => {
                Err(Failure::Abort(code.code()))
            }
            other => Err(Failure::Protocol(format!(
                "the slave answered the download with {other:?}"
            ))),
        };
        Ok(true)
    })
    .await
    .map_err(|f| match f {
        Failure::TooLong { mailbox, .. } => Failure::Protocol(format!(
            "{} bytes do not fit the slave's {mailbox}-byte mailbox (segmented download is not \
             supported over EtherCAT)",
            data.len()
        )),
        other => other,
    })?;
    done
}

/// One SDO Information request to the slave at `station`: the whole answer's OpCode and data,
/// its fragments joined.
async fn sdo_info(
    maindevice: &MainDevice<'_>,
    station: u16,
    request: info::Request,
    timeout: Duration,
) -> Result<(u8, Vec<u8>), Failure> {
    let mailbox = MailboxHeader::wrap(MailboxType::Coe, 0, 0, &info::request(request));
    let mut whole = info::Reassembly::new();
    let mut answer = None;
    mailbox_exchange(maindevice, station, mailbox, timeout, |body| {
        match whole.push(body) {
            Ok(Some(done)) => {
                answer = Some(done);
                Ok(true)
            }
            Ok(None) => Ok(false),
            Err(info::InfoError::Refused(code)) => Err(Failure::Abort(code.code())),
            Err(e) => Err(Failure::Protocol(e.to_string())),
        }
    })
    .await?;
    answer.ok_or(Failure::Timeout)
}

/// One object of a slave's dictionary as SDO Information describes it, with its entries (those the
/// slave has: a sub-index it answers "does not exist" for is left out).
#[derive(Debug, Clone)]
pub struct InfoObject {
    /// The description of the object.
    pub object: info::ObjectDescription,
    /// Its entries, in sub-index order.
    pub entries: Vec<info::EntryDescription>,
}

impl EthercatSession {
    /// The slaves of the chain.
    pub fn slave_count(&self) -> usize {
        self.group.len()
    }

    /// One SDO Information request to the slave at `node` (its position): the whole answer.
    fn info(&mut self, node: u8, request: info::Request) -> Result<(u8, Vec<u8>), ToolError> {
        self.check_node(node)?;
        let addr = match request {
            info::Request::Object(index) => Address::new(index, 0),
            info::Request::Entry { index, sub, .. } => Address::new(index, sub),
            info::Request::OdList(_) => Address::new(0, 0),
        };
        let (group, maindevice, timeout) = (&self.group, &self.link.maindevice, self.link.timeout);
        let r = drive(&mut self.link.tx_rx, async {
            let sd = group
                .subdevice(maindevice, usize::from(node) - 1)
                .map_err(Failure::Master)?;
            sdo_info(maindevice, sd.configured_address(), request, timeout).await
        })
        .map_err(|e| self.link.ended(e))?;
        r.map_err(|f| match (request, f) {
            (info::Request::OdList(_), Failure::Abort(code)) => EthercatError::Protocol {
                addr,
                position: node,
                detail: format!(
                    "SDO Information refused the object list: {}",
                    AbortCode::from(code)
                ),
            }
            .into(),
            (_, f) => self.link.error(node, addr, f),
        })
    }

    /// SDO Information's description of the entry `addr` on the slave at `node`.
    pub fn entry_description(
        &mut self,
        node: u8,
        addr: Address,
    ) -> Result<info::EntryDescription, ToolError> {
        let (_, data) = self.info(
            node,
            info::Request::Entry {
                index: addr.index,
                sub: addr.sub,
                value_info: 0,
            },
        )?;
        self.parsed(node, addr, info::EntryDescription::parse(&data))
    }

    /// An answer's data read as a description, or the protocol error naming it.
    fn parsed<T>(
        &self,
        node: u8,
        addr: Address,
        r: Result<T, info::InfoError>,
    ) -> Result<T, ToolError> {
        r.map_err(|e| {
            EthercatError::Protocol {
                addr,
                position: node,
                detail: e.to_string(),
            }
            .into()
        })
    }

    /// The dictionary of the slave at `node` as SDO Information gives it (ETG.1000.6 §5.6.3): every
    /// object of list 1 (all objects), each with its description and those of its entries
    /// 0..=MaxSubindex (a sub-index the slave says does not exist, 0x06090011, is left out).
    pub fn sdos(&mut self, node: u8) -> Result<Vec<InfoObject>, ToolError> {
        let list = info::OdList::All;
        let (_, data) = self.info(node, info::Request::OdList(list))?;
        let indices = self.parsed(node, Address::new(0, 0), info::od_list_indices(list, &data))?;
        let mut objects = Vec::with_capacity(indices.len());
        for index in indices {
            let addr = Address::new(index, 0);
            let (_, data) = self.info(node, info::Request::Object(index))?;
            let object = self.parsed(node, addr, info::ObjectDescription::parse(&data))?;
            let mut entries = Vec::new();
            for sub in 0..=object.max_sub {
                match self.entry_description(node, Address::new(index, sub)) {
                    Ok(e) => entries.push(e),
                    Err(ToolError::Abort {
                        code: AbortCode::NoSubIndex,
                        ..
                    }) => {}
                    Err(e) => return Err(e),
                }
            }
            objects.push(InfoObject { object, entries });
        }
        Ok(objects)
    }
}

impl SdoAccess for EthercatSession {
    fn check_node(&self, node: u8) -> Result<(), ToolError> {
        self.link.check_position(node, self.group.len())
    }

    fn read_bytes(&mut self, node: u8, addr: Address) -> Result<Vec<u8>, ToolError> {
        self.check_node(node)?;
        let (group, maindevice) = (&self.group, &self.link.maindevice);
        let sd = group.subdevice(maindevice, usize::from(node) - 1);
        let r = drive(&mut self.link.tx_rx, upload(sd, addr)).map_err(|e| self.link.ended(e))?;
        self.link.uploaded(node, addr, r)
    }

    /// The type SDO Information gives the entry; `None` when it is no basic type, or when the slave
    /// gives no SDO Information (the caller then asks for a type).
    fn entry_type(&mut self, node: u8, addr: Address) -> Result<Option<DataType>, ToolError> {
        match self.entry_description(node, addr) {
            Ok(e) => Ok(info::data_type(e.data_type)),
            // The entry is not there: as the read itself would say.
            Err(e @ ToolError::Abort { .. }) => Err(e),
            Err(_) => Ok(None),
        }
    }

    fn write_bytes(&mut self, node: u8, addr: Address, data: &[u8]) -> Result<(), ToolError> {
        self.check_node(node)?;
        let (group, maindevice, timeout) = (&self.group, &self.link.maindevice, self.link.timeout);
        let sd = group.subdevice(maindevice, usize::from(node) - 1);
        let r = drive(
            &mut self.link.tx_rx,
            download(maindevice, sd, addr, data, timeout),
        )
        .map_err(|e| self.link.ended(e))?;
        r.map_err(|f| self.link.error(node, addr, f))
    }
}

/// Reads `addr` from the slave `sd` (in any state).
async fn upload<S: std::ops::Deref<Target = ethercrab::SubDevice>>(
    sd: Result<ethercrab::SubDeviceRef<'_, S>, Error>,
    addr: Address,
) -> Result<heapless::Vec<u8, MAX_UPLOAD>, Error> {
    sd?.sdo_read::<heapless::Vec<u8, MAX_UPLOAD>>(addr.index, addr.sub)
        .await
}

/// Writes `data` to `addr` on the slave `sd` (in any state): expedited up to 4 bytes, else a
/// normal download.
async fn download<S: std::ops::Deref<Target = ethercrab::SubDevice>>(
    maindevice: &MainDevice<'_>,
    sd: Result<ethercrab::SubDeviceRef<'_, S>, Error>,
    addr: Address,
    data: &[u8],
    timeout: Duration,
) -> Result<(), Failure> {
    let sd = sd?;
    if (1..=4).contains(&data.len()) {
        sd.sdo_write(addr.index, addr.sub, data).await?;
        Ok(())
    } else {
        let mux = Address::new(addr.index, addr.sub);
        normal_download(maindevice, sd.configured_address(), mux, data, timeout).await
    }
}

impl Link {
    /// Whether `node` is a position of a chain of `count` slaves; a usage error says why not.
    fn check_position(&self, node: u8, count: usize) -> Result<(), ToolError> {
        if (1..=count).contains(&usize::from(node)) {
            Ok(())
        } else {
            Err(crate::UsageError::SlavePosition {
                position: u16::from(node),
                count,
                interface: self.interface.clone(),
            }
            .into())
        }
    }

    /// An upload's outcome in the tool's words.
    fn uploaded(
        &self,
        node: u8,
        addr: Address,
        r: Result<heapless::Vec<u8, MAX_UPLOAD>, Error>,
    ) -> Result<Vec<u8>, ToolError> {
        match r {
            Ok(bytes) => Ok(bytes.to_vec()),
            Err(Error::Mailbox(MailboxError::TooLong { .. })) => Err(self.error(
                node,
                addr,
                Failure::Protocol(format!("longer than {MAX_UPLOAD} bytes")),
            )),
            Err(e) => Err(self.error(node, addr, e.into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{beyond_init, mailbox_error};

    /// ETG.1000.4 §5.6's mailbox error codes.
    #[test]
    fn mailbox_errors_have_their_meanings() {
        let table = [
            (1, "syntax of the mailbox header"),
            (2, "mailbox protocol not supported"),
            (3, "channel field invalid"),
            (4, "service not supported"),
            (5, "invalid mailbox header"),
            (6, "mailbox data too short"),
            (7, "no more memory in the slave"),
            (8, "inconsistent data length"),
            (0, "unknown code"),
            (9, "unknown code"),
        ];
        for (code, meaning) in table {
            assert_eq!(mailbox_error(code), meaning, "{code}");
        }
    }

    /// The highest state in the OR of every slave's AL status (Init 1, Pre-Op 2, Bootstrap 3,
    /// Safe-Op 4, Op 8; the error flag 0x10 aside); `None` only when all are in Init.
    #[test]
    fn the_highest_state_beyond_init() {
        for (al, state) in [
            (0x0001, None),
            (0x0011, None),
            (0x0000, None),
            (0x0002, Some("Pre-Op")),
            (0x0003, Some("Bootstrap")),
            (0x0004, Some("Safe-Op")),
            (0x0014, Some("Safe-Op")),
            (0x0006, Some("Safe-Op")),
            (0x0008, Some("Op")),
            (0x000E, Some("Op")),
            (0x0009, Some("Op")),
        ] {
            assert_eq!(beyond_init(al), state, "0x{al:04X}");
        }
    }
}
