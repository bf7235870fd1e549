//! A chain looked at one datagram at a time, whoever runs it: the read-only look of `slaves` and
//! `states` and of the check before a session, and the register and EEPROM access of the commands
//! IgH's `ethercat` tool has (`reg-read`, `reg-write`, `sii-read`, `sii-write`, `alias`).
//!
//! Every datagram goes on a raw socket of its own with a frame index above the 16 frame buffers of
//! SOEM ([`PROBE_INDEX`]), so that the frames of another master on the same interface neither
//! disturb it nor are disturbed. Slaves are addressed by position (auto-increment addressing), so
//! nothing needs a configured station address. A [`Chain`]'s positions are 1 for the first slave,
//! as everywhere in the tool.
//!
//! The EEPROM (SII) is reached through the ESC's EEPROM interface (ETG.1000.4 §6.4, ESC datasheet
//! section II 0x0500–0x050F): 0x0500 who has the EEPROM (bit 0: offered to the PDI; 0x0501 bit 0:
//! the PDI has it), 0x0502 control and status (bit 0 write enable, bit 6: 8 bytes read at once,
//! bits 8–10 the command: 1 read, 2 write, 4 reload; bit 11 checksum error, bit 12 EEPROM not
//! loaded, bit 13 command error, bit 14 write enable error, bit 15 busy), 0x0504 the word address,
//! 0x0508 the data. A read command and its address go in one datagram (as SOEM writes them), then
//! control, address and data are read back together until the interface is no longer busy.

use std::time::{Duration, Instant};

use super::{check_interface_name, EthercatError, AL_STATUS};
use crate::link::{Capture, RawSocket};
use crate::ToolError;

/// The frame index of a probe's first try (the second and third take the next two): above the 16
/// frame buffers of SOEM, so a master running the chain never takes the probe's answer for its own,
/// nor this probe its frames.
pub const PROBE_INDEX: u8 = 0xE5;

/// Datagram commands (ETG.1000.4 Table 14).
const APRD: u8 = 0x01;
const APWR: u8 = 0x02;
const BRD: u8 = 0x07;

/// The EEPROM interface's registers.
const EEPROM_CONFIG: u16 = 0x0500;
pub(super) const EEPROM_CONTROL: u16 = 0x0502;
pub(super) const EEPROM_ADDRESS: u16 = 0x0504;
pub(super) const EEPROM_DATA: u16 = 0x0508;
/// EEPROM commands in 0x0502 (bits 8–10; write enable is bit 0).
pub(super) const READ: u16 = 0x0100;
const WRITE: u16 = 0x0201;
const RELOAD: u16 = 0x0400;
/// EEPROM status bits of 0x0502.
const READ_8: u16 = 1 << 6;
const CHECKSUM_ERROR: u16 = 1 << 11;
const NOT_LOADED: u16 = 1 << 12;
const COMMAND_ERROR: u16 = 1 << 13;
const WRITE_ENABLE_ERROR: u16 = 1 << 14;
pub(super) const BUSY: u16 = 1 << 15;

/// The most data one datagram of a probe carries (a frame holds 1,486 bytes of datagram data).
pub const MAX_DATAGRAM: usize = 1024;

/// The raw socket on `interface`, its frames written to `capture` where there is one: a missing
/// interface and a missing privilege each said in their own words.
pub(crate) fn open_socket(
    interface: &str,
    capture: Option<&Capture>,
) -> Result<RawSocket, EthercatError> {
    use ecat_link::raw::RawError;
    let mut socket = RawSocket::open(interface).map_err(|e| match e {
        RawError::NoInterface(_) => EthercatError::NoInterface {
            interface: interface.to_string(),
        },
        RawError::Io { source, .. } if source.kind() == std::io::ErrorKind::PermissionDenied => {
            EthercatError::Interface {
                interface: interface.to_string(),
                source: std::io::Error::new(
                    source.kind(),
                    "the raw socket needs root or CAP_NET_RAW",
                ),
            }
        }
        RawError::Io { source, .. } => EthercatError::Interface {
            interface: interface.to_string(),
            source,
        },
        other => EthercatError::Interface {
            interface: interface.to_string(),
            source: std::io::Error::other(other.to_string()),
        },
    })?;
    if let Some(c) = capture {
        socket.capture_to(c);
    }
    Ok(socket)
}

/// One datagram at a time on a raw socket of its own, with the frame index [`PROBE_INDEX`].
pub(crate) struct Probe {
    socket: RawSocket,
    buf: Vec<u8>,
}

impl Probe {
    /// The raw socket on `interface` (see [`open_socket`]).
    pub(crate) fn open(interface: &str, capture: Option<&Capture>) -> Result<Probe, EthercatError> {
        let socket = open_socket(interface, capture)?;
        Ok(Probe {
            socket,
            buf: vec![0u8; 2048],
        })
    }

    /// `cmd` at `adp`/`ado` with `data` (its length is the datagram's): the data and working counter
    /// of the answer, or `None` when none comes within 3 × 100 ms.
    pub(crate) fn exchange(
        &mut self,
        cmd: u8,
        adp: u16,
        ado: u16,
        data: &[u8],
    ) -> Option<(Vec<u8>, u16)> {
        let len = data.len();
        let mut frame = vec![0u8; (16 + 12 + len).max(60)];
        frame[..6].fill(0xFF);
        frame[6..12].fill(0x10);
        frame[12..14].copy_from_slice(&[0x88, 0xA4]);
        frame[14..16].copy_from_slice(&(0x1000u16 | (12 + len) as u16).to_le_bytes());
        frame[16] = cmd;
        frame[17] = PROBE_INDEX;
        frame[18..20].copy_from_slice(&adp.to_le_bytes());
        frame[20..22].copy_from_slice(&ado.to_le_bytes());
        frame[22..24].copy_from_slice(&(len as u16).to_le_bytes());
        frame[26..26 + len].copy_from_slice(data);
        // Each try has its own index; an answer to an earlier try that comes after a later one was
        // sent is taken too. Once answered, the answers still on their way are awaited, so that
        // none reaches a master's socket opened next (ethercrab would take it for one of its own).
        let mut answer = None;
        let mut sent = 0u8;
        let mut answered = 0u8;
        'tries: for k in 0..3u8 {
            frame[17] = PROBE_INDEX + k;
            self.socket.send(&frame).ok()?;
            sent += 1;
            let deadline = Instant::now() + Duration::from_millis(100);
            loop {
                let left = deadline.saturating_duration_since(Instant::now());
                match self.socket.recv(&mut self.buf) {
                    // An answer: from a slave (locally administered source), one of our
                    // indexes, our command at our address with our length.
                    Ok(Some(n))
                        if n >= 28 + len
                            && self.buf[6] & 0x02 != 0
                            && (PROBE_INDEX..PROBE_INDEX + sent).contains(&self.buf[17])
                            && self.buf[16] == cmd
                            && self.buf[20..22] == ado.to_le_bytes()
                            && usize::from(
                                u16::from_le_bytes([self.buf[22], self.buf[23]]) & 0x07FF,
                            ) == len =>
                    {
                        let b = &self.buf;
                        let wkc = u16::from_le_bytes([b[26 + len], b[27 + len]]);
                        answered += 1;
                        answer.get_or_insert((b[26..26 + len].to_vec(), wkc));
                        break 'tries;
                    }
                    Ok(Some(_)) => {}
                    Ok(None) if !left.is_zero() => {
                        self.socket.wait(left).ok()?;
                    }
                    Ok(None) => break,
                    Err(_) => return None,
                }
            }
        }
        let deadline = Instant::now() + Duration::from_millis(300);
        while answer.is_some() && answered < sent && Instant::now() < deadline {
            match self.socket.recv(&mut self.buf) {
                Ok(Some(n))
                    if n >= 18
                        && self.buf[6] & 0x02 != 0
                        && (PROBE_INDEX..PROBE_INDEX + sent).contains(&self.buf[17]) =>
                {
                    answered += 1;
                }
                Ok(Some(_)) => {}
                Ok(None) => {
                    let _ = self
                        .socket
                        .wait(deadline.saturating_duration_since(Instant::now()));
                }
                Err(_) => break,
            }
        }
        answer
    }

    /// Registers of the slave at 0-based `position` (auto-increment addressing).
    pub(crate) fn read(&mut self, position: u16, ado: u16, len: usize) -> Result<Vec<u8>, Missed> {
        let (data, wkc) = self
            .exchange(APRD, position.wrapping_neg(), ado, &vec![0; len])
            .ok_or(Missed::NoAnswer)?;
        if wkc != 1 {
            return Err(Missed::WorkingCounter(wkc));
        }
        Ok(data)
    }

    /// Writes registers of the slave at 0-based `position`.
    fn write(&mut self, position: u16, ado: u16, data: &[u8]) -> Result<(), Missed> {
        let (_, wkc) = self
            .exchange(APWR, position.wrapping_neg(), ado, data)
            .ok_or(Missed::NoAnswer)?;
        if wkc != 1 {
            return Err(Missed::WorkingCounter(wkc));
        }
        Ok(())
    }
}

/// Why a datagram to one slave was not served.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Missed {
    /// No frame came back within 3 × 100 ms.
    NoAnswer,
    /// The frame came back with this working counter, not 1.
    WorkingCounter(u16),
}

impl std::fmt::Display for Missed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Missed::NoAnswer => f.write_str("no frame came back within 3 × 100 ms"),
            Missed::WorkingCounter(wkc) => write!(f, "working counter {wkc}, not 1"),
        }
    }
}

/// Every slave's AL status OR'd (one BRD of 0x0130), or `None` when no slave answers.
pub(crate) fn al_status(
    interface: &str,
    capture: Option<&Capture>,
) -> Result<Option<u16>, EthercatError> {
    let answer = Probe::open(interface, capture)?.exchange(BRD, 0, AL_STATUS, &[0, 0]);
    Ok(answer
        .filter(|(_, wkc)| *wkc > 0)
        .map(|(data, _)| u16::from_le_bytes([data[0], data[1]])))
}

/// The AL state of an AL status, as IgH's tool writes it (`alStateString`): INIT, PREOP, BOOT,
/// SAFEOP or OP, `???` for another code, `+ERROR` after it when the error flag (bit 4) is set.
pub fn state_name(al: u16) -> String {
    let state = match al & 0x0F {
        0x01 => "INIT",
        0x02 => "PREOP",
        0x03 => "BOOT",
        0x04 => "SAFEOP",
        0x08 => "OP",
        _ => "???",
    };
    if al & 0x10 != 0 {
        format!("{state}+ERROR")
    } else {
        state.to_string()
    }
}

/// A slave's SII image as read from its EEPROM.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SiiRead {
    /// The words up to and with the End category's type word.
    pub bytes: Vec<u8>,
    /// The categories did not end within [`od::sii::MAX_WORDS`]: `bytes` are the 64 header words
    /// only, as IgH's master takes them.
    pub cut: bool,
}

/// A chain on one interface, looked at and written to datagram by datagram.
pub struct Chain {
    probe: Probe,
    interface: String,
    count: u16,
    timeout: Duration,
}

impl Chain {
    /// Opens `interface` and counts its slaves (one broadcast read of 0x0000); `timeout` bounds each
    /// wait for the EEPROM interface; every frame goes to `capture` too, where there is one.
    pub fn open(
        interface: &str,
        timeout: Duration,
        capture: Option<&Capture>,
    ) -> Result<Chain, ToolError> {
        check_interface_name(interface)?;
        let mut probe = Probe::open(interface, capture)?;
        // No frame back, or one no slave counted: no chain.
        let Some(count) = probe
            .exchange(BRD, 0, 0x0000, &[0])
            .map(|(_, wkc)| wkc)
            .filter(|wkc| *wkc > 0)
        else {
            return Err(EthercatError::NoSlaves {
                interface: interface.to_string(),
            }
            .into());
        };
        Ok(Chain {
            probe,
            interface: interface.to_string(),
            count,
            timeout,
        })
    }

    /// The chain's network interface.
    pub fn interface(&self) -> &str {
        &self.interface
    }

    /// The slaves that answered the count.
    pub fn count(&self) -> u16 {
        self.count
    }

    /// Whether `position` (1 = first) is a slave of the chain; a usage error says why not.
    pub fn check_position(&self, position: u16) -> Result<(), ToolError> {
        if (1..=self.count).contains(&position) {
            Ok(())
        } else {
            Err(crate::UsageError::SlavePosition {
                position,
                count: usize::from(self.count),
                interface: self.interface.clone(),
            }
            .into())
        }
    }

    fn no_answer(&self, position: u16, what: String, why: Missed) -> ToolError {
        EthercatError::NoAnswer {
            interface: self.interface.clone(),
            position,
            what: format!("{what}: {why}"),
        }
        .into()
    }

    /// `len` bytes of the registers of the slave at `position` from `address`, in datagrams of at
    /// most [`MAX_DATAGRAM`] bytes.
    pub fn read(&mut self, position: u16, address: u16, len: usize) -> Result<Vec<u8>, ToolError> {
        self.check_position(position)?;
        let mut out = Vec::with_capacity(len);
        while out.len() < len {
            let at = address.wrapping_add(out.len() as u16);
            let n = (len - out.len()).min(MAX_DATAGRAM);
            let part = self.probe.read(position - 1, at, n).map_err(|why| {
                self.no_answer(
                    position,
                    format!("the read of 0x{at:04X} ({n} byte{})", plural(n)),
                    why,
                )
            })?;
            out.extend_from_slice(&part);
        }
        Ok(out)
    }

    /// Writes `data` to the registers of the slave at `position` from `address`, in datagrams of at
    /// most [`MAX_DATAGRAM`] bytes.
    pub fn write(&mut self, position: u16, address: u16, data: &[u8]) -> Result<(), ToolError> {
        self.check_position(position)?;
        for (k, part) in data.chunks(MAX_DATAGRAM).enumerate() {
            let at = address.wrapping_add((k * MAX_DATAGRAM) as u16);
            self.probe.write(position - 1, at, part).map_err(|why| {
                self.no_answer(
                    position,
                    format!(
                        "the write of 0x{at:04X} ({} byte{})",
                        part.len(),
                        plural(part.len())
                    ),
                    why,
                )
            })?;
        }
        Ok(())
    }

    fn eeprom_error(&self, position: u16, detail: String) -> ToolError {
        EthercatError::Eeprom {
            interface: self.interface.clone(),
            position,
            detail,
        }
        .into()
    }

    /// The EEPROM interface to the master (ECAT): refused while the slave's PDI has the EEPROM
    /// (0x0501 bit 0); taken back when only offered to it (0x0500 bit 0), as IgH's tool does.
    fn take_eeprom(&mut self, position: u16) -> Result<(), ToolError> {
        let config = self.read(position, EEPROM_CONFIG, 2)?;
        if config[1] & 0x01 != 0 {
            return Err(self.eeprom_error(
                position,
                "the slave's PDI has the EEPROM (0x0501 bit 0)".to_string(),
            ));
        }
        if config[0] & 0x01 != 0 {
            self.write(position, EEPROM_CONFIG, &[0])?;
        }
        Ok(())
    }

    /// 0x0502–0x050F once the EEPROM interface is no longer busy (at most the chain's timeout).
    fn eeprom_idle(&mut self, position: u16) -> Result<(u16, Vec<u8>), ToolError> {
        let deadline = Instant::now() + self.timeout;
        loop {
            let r = self.read(position, EEPROM_CONTROL, 14)?;
            let status = u16::from_le_bytes([r[0], r[1]]);
            if status & BUSY == 0 {
                return Ok((status, r[6..].to_vec()));
            }
            if Instant::now() >= deadline {
                return Err(self.eeprom_error(
                    position,
                    format!(
                        "still busy after {} ms (0x0502 = 0x{status:04X})",
                        self.timeout.as_millis()
                    ),
                ));
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// One EEPROM command with its word address; the status after it, and the data register.
    fn eeprom_command(
        &mut self,
        position: u16,
        command: u16,
        word: u32,
    ) -> Result<(u16, Vec<u8>), ToolError> {
        let mut request = command.to_le_bytes().to_vec();
        request.extend_from_slice(&word.to_le_bytes());
        self.write(position, EEPROM_CONTROL, &request)?;
        let (status, data) = self.eeprom_idle(position)?;
        let error = status & (COMMAND_ERROR | WRITE_ENABLE_ERROR);
        if error != 0 {
            let what = match command {
                READ => format!("the read of word 0x{word:04X}"),
                WRITE => format!("the write of word 0x{word:04X}"),
                _ => "the reload".to_string(),
            };
            return Err(self.eeprom_error(
                position,
                format!("{what} was refused (0x0502 = 0x{status:04X})"),
            ));
        }
        Ok((status, data))
    }

    /// 4 or 8 bytes (as the ESC reads them at once) of the EEPROM from `word`.
    fn eeprom_read(&mut self, position: u16, word: u32) -> Result<Vec<u8>, ToolError> {
        let (status, mut data) = self.eeprom_command(position, READ, word)?;
        data.truncate(if status & READ_8 != 0 { 8 } else { 4 });
        Ok(data)
    }

    /// The SII image of the slave at `position`: the header, then each category, up to the End
    /// category ([`od::sii::extent`]), as IgH's master reads it.
    pub fn sii(&mut self, position: u16) -> Result<SiiRead, ToolError> {
        use od::sii::Extent;
        self.check_position(position)?;
        self.take_eeprom(position)?;
        let mut bytes = Vec::new();
        loop {
            match od::sii::extent(&bytes) {
                Extent::Complete(n) => {
                    bytes.truncate(n);
                    return Ok(SiiRead { bytes, cut: false });
                }
                Extent::TooLong => {
                    bytes.truncate(od::sii::FIRST_CATEGORY);
                    return Ok(SiiRead { bytes, cut: true });
                }
                Extent::More(n) => {
                    while bytes.len() < n {
                        let word = (bytes.len() / 2) as u32;
                        let data = self.eeprom_read(position, word)?;
                        bytes.extend_from_slice(&data);
                    }
                }
            }
        }
    }

    /// `n` words of the EEPROM of the slave at `position` from `word`.
    pub fn sii_words(&mut self, position: u16, word: u32, n: usize) -> Result<Vec<u8>, ToolError> {
        self.check_position(position)?;
        self.take_eeprom(position)?;
        let mut bytes = Vec::with_capacity(2 * n + 8);
        while bytes.len() < 2 * n {
            let data = self.eeprom_read(position, word + (bytes.len() / 2) as u32)?;
            bytes.extend_from_slice(&data);
        }
        bytes.truncate(2 * n);
        Ok(bytes)
    }

    /// The bytes the EEPROM of the slave at `position` holds as its SII says (word 0x3E: the size in
    /// Kibit less one), or `None` when that word is blank (0xFFFF).
    pub fn eeprom_size(&mut self, position: u16) -> Result<Option<usize>, ToolError> {
        let w = self.sii_words(position, 0x3E, 1)?;
        let kibit = u16::from_le_bytes([w[0], w[1]]);
        Ok((kibit != 0xFFFF).then(|| (usize::from(kibit) + 1) * 128))
    }

    /// Writes `bytes` (whole words) into the EEPROM of the slave at `position` from word 0, one
    /// word at a time, each with write enable, as IgH's master writes an SII.
    pub fn write_sii(&mut self, position: u16, bytes: &[u8]) -> Result<(), ToolError> {
        self.check_position(position)?;
        self.take_eeprom(position)?;
        for (k, word) in bytes.chunks_exact(2).enumerate() {
            self.write(position, EEPROM_DATA, word)?;
            self.eeprom_command(position, WRITE, k as u32)?;
        }
        Ok(())
    }

    /// Has the slave's ESC load its configuration from the EEPROM again (the reload command), which
    /// puts SII word 4 into the alias register 0x0012.
    pub fn reload_sii(&mut self, position: u16) -> Result<(), ToolError> {
        self.check_position(position)?;
        let (status, _) = self.eeprom_command(position, RELOAD, 0)?;
        if status & (CHECKSUM_ERROR | NOT_LOADED) != 0 {
            return Err(self.eeprom_error(
                position,
                format!(
                    "the reload found no valid configuration (0x0502 = 0x{status:04X}: checksum \
                     error or not loaded)"
                ),
            ));
        }
        Ok(())
    }
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// One slave as `slaves` and `states` show it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlaveInfo {
    /// 1-based position in the chain.
    pub position: u16,
    /// AL status (0x0130).
    pub al_status: u16,
    /// AL status code (0x0134).
    pub al_code: u16,
}

/// The slaves of the chain on `interface`, read only: one broadcast read counts them, then per
/// position its AL status and code. Any chain, in any state, whoever runs it.
pub fn states(
    interface: &str,
    timeout: Duration,
    capture: Option<&Capture>,
) -> Result<Vec<SlaveInfo>, ToolError> {
    let mut chain = Chain::open(interface, timeout, capture)?;
    let mut out = Vec::new();
    for position in 1..=chain.count() {
        let al = chain.read(position, AL_STATUS, 6)?;
        out.push(SlaveInfo {
            position,
            al_status: u16::from_le_bytes([al[0], al[1]]),
            al_code: u16::from_le_bytes([al[4], al[5]]),
        });
    }
    Ok(out)
}
