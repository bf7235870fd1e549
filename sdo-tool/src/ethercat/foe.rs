//! FoE over the slaves' mailboxes (ethercrab 0.7 has no FoE): the master's side of a transfer
//! ([`od::foe::client`]) moved through the mailbox as [`super::mailbox`] puts requests in and takes
//! answers out, in packets of the slave's mailbox length less 12 bytes; and the way into
//! Bootstrap for firmware.
//!
//! - **Busy**: the packet goes again 2 ms later; a slave busy with one packet for more than ten
//!   answer timeouts fails the transfer as a timeout.
//! - **Errors**: the slave's Error frame ends the transfer with its code and text; a wrong answer
//!   (a packet out of turn, a frame that has no place) ends it with an Error frame sent to the
//!   slave (0x8005, 0x8004), so the slave ends it too.
//! - **Bootstrap** (`--boot`): the slave to Init, SM0 and SM1 at its bootstrap mailbox (SII words
//!   0x14–0x17: receive offset and size, send offset and size; the control bytes kept), then
//!   Bootstrap (ETG.1000.6 §6.4.1: from Init only). The session takes it back to Init at its end,
//!   as every slave.

use std::time::{Duration, Instant};

use ethercrab::{Command, MainDevice};
use od::coe::mailbox::{MailboxHeader, MailboxType};
use od::foe::client::{FoeError, FoeRead, FoeWrite, Next};
use od::foe::{data_per_packet, printable, FoeErrorCode};

use super::chain::{BUSY, EEPROM_ADDRESS, EEPROM_CONTROL, EEPROM_DATA, READ};
use super::mailbox::{Mailbox, SM0};
use super::{drive, mailbox_error, EthercatSession, Failure, AL_CONTROL, AL_STATUS};
use crate::ToolError;

/// The longest file `foe-read` takes: 256 MiB.
pub const MAX_FOE_READ: usize = 256 << 20;
/// The pause before a packet goes again after Busy.
const BUSY_PAUSE: Duration = Duration::from_millis(2);
/// AL status code register.
const AL_STATUS_CODE: u16 = 0x0134;
/// SII word of the bootstrap mailbox: receive offset, receive size, send offset, send size.
const SII_BOOT_MAILBOX: u32 = 0x0014;

/// Why an FoE transfer failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FoeFailure {
    /// The slave ended it with an Error frame, or answered as the protocol does not.
    #[error("{}", foe_words(.0))]
    Foe(#[source] FoeError),
    /// No answer in time.
    #[error("failed: no answer within {ms} ms")]
    Timeout {
        /// The timeout.
        ms: u128,
    },
    /// The slave answered with a mailbox error (2: it has no FoE).
    #[error("failed: the slave answered with mailbox error {code} ({})", mailbox_error(*code))]
    Mailbox {
        /// The error's code.
        code: u16,
    },
    /// The slave did not go to Bootstrap.
    #[error(
        "failed: the slave did not go to Bootstrap (AL status 0x{status:04X}, AL status code 0x{code:04X})"
    )]
    Boot {
        /// AL status.
        status: u16,
        /// AL status code.
        code: u16,
    },
    /// ethercrab's error.
    #[error("failed: {0}")]
    Master(#[source] ethercrab::error::Error),
    /// Anything else of the protocol.
    #[error("failed: {0}")]
    Protocol(String),
}

/// An FoE error in words: `aborted with error code 0x00008009: Not Bootstrap.` for the slave's
/// Error frame, as IgH's tool writes it.
fn foe_words(e: &FoeError) -> String {
    match e {
        FoeError::Refused { .. } => format!("aborted with {e}"),
        other => format!("failed: {other}"),
    }
}

impl FoeFailure {
    /// The slave refused the transfer with an FoE Error frame: `code`.
    pub fn refused(&self) -> Option<FoeErrorCode> {
        match self {
            FoeFailure::Foe(FoeError::Refused { code, .. }) => Some(*code),
            _ => None,
        }
    }

    fn from_failure(f: Failure, timeout: Duration) -> FoeFailure {
        match f {
            Failure::Master(e) => FoeFailure::Master(e),
            Failure::Timeout => FoeFailure::Timeout {
                ms: timeout.as_millis(),
            },
            Failure::MailboxError(code) => FoeFailure::Mailbox { code },
            Failure::Abort(code) => FoeFailure::Protocol(format!("an SDO abort 0x{code:08X}")),
            Failure::Protocol(p) => FoeFailure::Protocol(p),
            Failure::TooLong { bytes, mailbox } => FoeFailure::Protocol(format!(
                "a {bytes}-byte request does not fit the slave's {mailbox}-byte mailbox"
            )),
        }
    }
}

/// One FoE transfer: a write or a read.
enum Transfer {
    Write(FoeWrite),
    Read(FoeRead),
}

impl Transfer {
    fn request(&mut self) -> Vec<u8> {
        match self {
            Transfer::Write(w) => w.request(),
            Transfer::Read(r) => r.request(),
        }
    }

    fn handle(&mut self, answer: &[u8]) -> Result<Next, FoeError> {
        match self {
            Transfer::Write(w) => w.handle(answer),
            Transfer::Read(r) => r.handle(answer),
        }
    }
}

/// Runs `transfer` (made for the mailbox's lengths by `make`) with the slave at `station`, in
/// Bootstrap first when `boot`.
async fn run(
    maindevice: &MainDevice<'_>,
    station: u16,
    timeout: Duration,
    boot: bool,
    make: impl FnOnce(&Mailbox) -> Transfer,
) -> Result<Transfer, FoeFailure> {
    let failed = |f| FoeFailure::from_failure(f, timeout);
    if boot {
        to_boot(maindevice, station, timeout).await?;
    }
    let mailbox = Mailbox::of(maindevice, station).await.map_err(failed)?;
    let mut transfer = make(&mailbox);
    mailbox.drain(maindevice).await.map_err(failed)?;
    let wrap = |frame: &[u8]| MailboxHeader::wrap(MailboxType::Foe, 0, 0, frame);
    let mut frame = transfer.request();
    let mut busy_since: Option<Instant> = None;
    let mut answered = false;
    loop {
        // Once the slave answered, it has taken the request before: its write mailbox is empty.
        if answered {
            mailbox.send_taken(maindevice, wrap(&frame)).await
        } else {
            mailbox.send(maindevice, wrap(&frame), timeout).await
        }
        .map_err(failed)?;
        answered = true;
        let (t, answer) = mailbox.receive(maindevice, timeout).await.map_err(failed)?;
        if t != MailboxType::Foe {
            return Err(FoeFailure::Protocol(format!(
                "the slave answered with a mailbox of type {}, not FoE (4)",
                t.code()
            )));
        }
        match transfer.handle(&answer) {
            Ok(Next::Send(next)) => {
                frame = next;
                busy_since = None;
            }
            Ok(Next::Busy { again, .. }) => {
                let since = *busy_since.get_or_insert_with(Instant::now);
                if since.elapsed() > 10 * timeout {
                    return Err(failed(Failure::Timeout));
                }
                async_io::Timer::after(BUSY_PAUSE).await;
                frame = again;
            }
            Ok(Next::SendLast(last)) => {
                let sent = mailbox.send_taken(maindevice, wrap(&last)).await;
                sent.map_err(failed)?;
                return Ok(transfer);
            }
            Ok(Next::Done) => return Ok(transfer),
            Err(e) => {
                if let Some(abort) = e.abort_frame() {
                    let _ = mailbox.send_taken(maindevice, wrap(&abort)).await;
                }
                return Err(FoeFailure::Foe(e));
            }
        }
    }
}

/// The slave at `station` to Init, its mailbox to the bootstrap mailbox of its SII, and to
/// Bootstrap.
async fn to_boot(
    maindevice: &MainDevice<'_>,
    station: u16,
    timeout: Duration,
) -> Result<(), FoeFailure> {
    let failed = |f: Failure| FoeFailure::from_failure(f, timeout);
    let master = |e: ethercrab::error::Error| FoeFailure::Master(e);
    let state = |to: u16| async move {
        Command::fpwr(station, AL_CONTROL)
            .send(maindevice, to | 0x10)
            .await
            .map_err(master)?;
        let deadline = Instant::now() + timeout;
        loop {
            let status: u16 = Command::fprd(station, AL_STATUS)
                .receive(maindevice)
                .await
                .map_err(master)?;
            if status & 0x1F == to {
                return Ok(());
            }
            if status & 0x10 != 0 || Instant::now() >= deadline {
                let code: u16 = Command::fprd(station, AL_STATUS_CODE)
                    .receive(maindevice)
                    .await
                    .map_err(master)?;
                return Err(FoeFailure::Boot { status, code });
            }
            async_io::Timer::after(Duration::from_millis(1)).await;
        }
    };
    state(0x01).await?;
    let mut words = [0u16; 4];
    for k in 0..2 {
        let pair = sii_pair(
            maindevice,
            station,
            SII_BOOT_MAILBOX + 2 * k as u32,
            timeout,
        )
        .await
        .map_err(failed)?;
        words[2 * k] = pair as u16;
        words[2 * k + 1] = (pair >> 16) as u16;
    }
    let sm: [u8; 16] = Command::fprd(station, SM0)
        .receive(maindevice)
        .await
        .map_err(master)?;
    for (n, (start, len), control) in [
        (0u16, (words[0], words[1]), sm[4]),
        (1, (words[2], words[3]), sm[12]),
    ] {
        let mut r = start.to_le_bytes().to_vec();
        r.extend_from_slice(&len.to_le_bytes());
        r.extend_from_slice(&[control, 0, 1, 0]);
        Command::fpwr(station, SM0 + 8 * n)
            .send_receive_slice(maindevice, r.as_slice())
            .await
            .map_err(master)?;
    }
    let boot = state(0x03).await;
    if boot.is_err() {
        // The refusal acknowledged: the slave stays in Init without the error indication.
        let _ = Command::fpwr(station, AL_CONTROL)
            .send(maindevice, 0x0011u16)
            .await;
    }
    boot
}

/// Two words of the SII of the slave at `station` from word `address`, through its EEPROM
/// interface.
async fn sii_pair(
    maindevice: &MainDevice<'_>,
    station: u16,
    address: u32,
    timeout: Duration,
) -> Result<u32, Failure> {
    Command::fpwr(station, EEPROM_ADDRESS)
        .send(maindevice, address)
        .await?;
    Command::fpwr(station, EEPROM_CONTROL)
        .send(maindevice, READ)
        .await?;
    let deadline = Instant::now() + timeout;
    loop {
        let status: u16 = Command::fprd(station, EEPROM_CONTROL)
            .receive(maindevice)
            .await?;
        if status & BUSY == 0 {
            break;
        }
        if Instant::now() >= deadline {
            return Err(Failure::Timeout);
        }
    }
    Ok(Command::fprd(station, EEPROM_DATA)
        .receive::<u32>(maindevice)
        .await?)
}

impl EthercatSession {
    /// The slave at `position` (1 = first) for `command`: `position` itself when given, else the
    /// chain's only one.
    pub fn single_slave(
        &self,
        position: Option<u8>,
        command: &'static str,
    ) -> Result<u8, ToolError> {
        use crate::SdoAccess;
        match position {
            Some(p) => {
                self.check_node(p)?;
                Ok(p)
            }
            None if self.slave_count() == 1 => Ok(1),
            None => Err(crate::UsageError::OneSlave {
                command,
                how: "-p POS",
                interface: self.link.interface.clone(),
                count: u16::try_from(self.slave_count()).unwrap_or(u16::MAX),
            }
            .into()),
        }
    }

    /// Runs a transfer with the slave at `position`; the error in the tool's words.
    fn foe(
        &mut self,
        op: &'static str,
        position: u8,
        name: &[u8],
        boot: bool,
        make: impl FnOnce(&Mailbox) -> Transfer,
    ) -> Result<Transfer, ToolError> {
        let position = self.single_slave(Some(position), op)?;
        let (group, maindevice, timeout) = (&self.group, &self.link.maindevice, self.link.timeout);
        let r = drive(&mut self.link.tx_rx, async {
            let sd = group
                .subdevice(maindevice, usize::from(position) - 1)
                .map_err(FoeFailure::Master)?;
            run(maindevice, sd.configured_address(), timeout, boot, make).await
        })
        .map_err(|e| self.link.ended(e))?;
        r.map_err(|source| {
            let hint = match source.refused() {
                Some(FoeErrorCode::NotBootstrap) if !boot => {
                    "; the slave takes this file in Bootstrap: --boot"
                }
                _ => "",
            };
            ToolError::Foe {
                position,
                op,
                file: printable(name),
                source,
                hint,
            }
        })
    }

    /// Writes `data` as the file `name` with `password` to the slave at `position` (in
    /// Bootstrap first when `boot`).
    pub fn foe_write(
        &mut self,
        position: u8,
        name: &[u8],
        password: u32,
        data: Vec<u8>,
        boot: bool,
    ) -> Result<(), ToolError> {
        self.foe("write", position, name, boot, |m| {
            Transfer::Write(FoeWrite::new(
                name,
                password,
                data,
                data_per_packet(m.write_len()),
            ))
        })
        .map(|_| ())
    }

    /// Reads the file `name` with `password` from the slave at `position` (in Bootstrap first
    /// when `boot`), [`MAX_FOE_READ`] bytes at most.
    pub fn foe_read(
        &mut self,
        position: u8,
        name: &[u8],
        password: u32,
        boot: bool,
    ) -> Result<Vec<u8>, ToolError> {
        let transfer = self.foe("read", position, name, boot, |m| {
            Transfer::Read(FoeRead::new(
                name,
                password,
                data_per_packet(m.read_len()),
                MAX_FOE_READ,
            ))
        })?;
        match transfer {
            Transfer::Read(r) => Ok(r.into_data()),
            Transfer::Write(_) => Ok(Vec::new()),
        }
    }
}
