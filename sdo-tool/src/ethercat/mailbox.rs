//! A slave's mailboxes as the tool uses them itself where ethercrab has no service (a normal
//! download, SDO Information, FoE): a request put into the slave's write mailbox (SM0), its answers
//! taken from its read mailbox (SM1), at the places and lengths the SyncManagers have now. Every
//! request carries mailbox counter 0 (no repeat detection, so ethercrab's own counter sequence is
//! not disturbed) and is padded to the mailbox's length.

use std::time::{Duration, Instant};

use ethercrab::{Command, MainDevice};
use od::coe::mailbox::{CoeHeader, CoeService, MailboxHeader, MailboxType};

use super::Failure;

/// SyncManager registers: SM0 (the master's write mailbox) at 0x0800, SM1 (its read mailbox) at
/// 0x0808, 8 bytes each; the status byte at offset 5.
pub(super) const SM0: u16 = 0x0800;
const SM1: u16 = 0x0808;
const SM_STATUS: u16 = 5;
/// SyncManager status bit 3: the mailbox is full.
const MAILBOX_FULL: u8 = 0x08;

/// The mailboxes of the slave at `station` as its SyncManagers set them.
#[derive(Debug, Clone, Copy)]
pub(super) struct Mailbox {
    station: u16,
    /// The write mailbox's start and length.
    write: (u16, u16),
    /// The read mailbox's start and length.
    read: (u16, u16),
}

impl Mailbox {
    /// The mailboxes of the slave at `station`, read from its SM0 and SM1 registers; none when
    /// they are no mailboxes.
    pub(super) async fn of(maindevice: &MainDevice<'_>, station: u16) -> Result<Mailbox, Failure> {
        let sm: [u8; 16] = Command::fprd(station, SM0).receive(maindevice).await?;
        let word = |k: usize| u16::from_le_bytes([sm[k], sm[k + 1]]);
        let is_mailbox = |control: u8| control & 0x03 == 0x02;
        let mailbox = Mailbox {
            station,
            write: (word(0), word(2)),
            read: (word(8), word(10)),
        };
        if !is_mailbox(sm[4]) || !is_mailbox(sm[12]) || mailbox.write.1 == 0 || mailbox.read.1 == 0
        {
            return Err(Failure::Protocol("the slave has no mailbox".into()));
        }
        Ok(mailbox)
    }

    /// The write mailbox's length.
    pub(super) fn write_len(&self) -> usize {
        usize::from(self.write.1)
    }

    /// The read mailbox's length.
    pub(super) fn read_len(&self) -> usize {
        usize::from(self.read.1)
    }

    /// Whether SyncManager `sm`'s mailbox is full.
    async fn full(&self, maindevice: &MainDevice<'_>, sm: u16) -> Result<bool, Failure> {
        let s: u8 = Command::fprd(self.station, sm + SM_STATUS)
            .receive(maindevice)
            .await?;
        Ok(s & MAILBOX_FULL != 0)
    }

    /// Until SyncManager `sm`'s mailbox is full (`full`) or empty, at most `timeout`.
    async fn until(
        &self,
        maindevice: &MainDevice<'_>,
        sm: u16,
        full: bool,
        timeout: Duration,
    ) -> Result<(), Failure> {
        let deadline = Instant::now() + timeout;
        while self.full(maindevice, sm).await? != full {
            if Instant::now() >= deadline {
                return Err(Failure::Timeout);
            }
            async_io::Timer::after(Duration::from_micros(200)).await;
        }
        Ok(())
    }

    /// Takes an answer nobody took from the read mailbox.
    pub(super) async fn drain(&self, maindevice: &MainDevice<'_>) -> Result<(), Failure> {
        if self.full(maindevice, SM1).await? {
            Command::fprd(self.station, self.read.0)
                .receive_slice(maindevice, self.read.1)
                .await?;
        }
        Ok(())
    }

    /// Puts `request` (a whole mailbox, padded here) into the write mailbox once it is empty (at
    /// most `timeout`).
    pub(super) async fn send(
        &self,
        maindevice: &MainDevice<'_>,
        request: Vec<u8>,
        timeout: Duration,
    ) -> Result<(), Failure> {
        self.until(maindevice, SM0, false, timeout).await?;
        self.send_taken(maindevice, request).await
    }

    /// Puts `request` into the write mailbox, which the slave has emptied: it answered the request
    /// before.
    pub(super) async fn send_taken(
        &self,
        maindevice: &MainDevice<'_>,
        mut request: Vec<u8>,
    ) -> Result<(), Failure> {
        if request.len() > self.write_len() {
            return Err(Failure::TooLong {
                bytes: request.len(),
                mailbox: self.write.1,
            });
        }
        request.resize(self.write_len(), 0);
        Command::fpwr(self.station, self.write.0)
            .send_receive_slice(maindevice, request.as_slice())
            .await?;
        Ok(())
    }

    /// The next answer in the read mailbox (at most `timeout`): its type and its data after the
    /// header. A mailbox error reply is [`Failure::MailboxError`]; a CoE emergency is passed over.
    pub(super) async fn receive(
        &self,
        maindevice: &MainDevice<'_>,
        timeout: Duration,
    ) -> Result<(MailboxType, Vec<u8>), Failure> {
        loop {
            self.until(maindevice, SM1, true, timeout).await?;
            let answer = Command::fprd(self.station, self.read.0)
                .receive_slice(maindevice, self.read.1)
                .await?;
            let (header, data) = MailboxHeader::split(&answer)
                .map_err(|e| Failure::Protocol(format!("the slave's answer is no mailbox: {e}")))?;
            match header.mailbox_type {
                MailboxType::Error => {
                    let code = data.get(2..4).map(|c| u16::from_le_bytes([c[0], c[1]]));
                    return Err(Failure::MailboxError(code.unwrap_or(0)));
                }
                MailboxType::Coe
                    if CoeHeader::parse(data).map(|h| h.service) == Ok(CoeService::Emergency) => {}
                t => return Ok((t, data.to_vec())),
            }
        }
    }
}

/// One request mailbox put into the write mailbox of the slave at `station`, and the answers taken
/// from its read mailbox, the data of each (after its mailbox header) given to `take` until it
/// says the answer is whole (`Ok(true)`); at most `timeout` for each answer mailbox. An answer
/// nobody took is taken first.
pub(super) async fn exchange(
    maindevice: &MainDevice<'_>,
    station: u16,
    request: Vec<u8>,
    timeout: Duration,
    mut take: impl FnMut(&[u8]) -> Result<bool, Failure>,
) -> Result<(), Failure> {
    let mailbox = Mailbox::of(maindevice, station).await?;
    if request.len() > mailbox.write_len() {
        return Err(Failure::TooLong {
            bytes: request.len(),
            mailbox: mailbox.write.1,
        });
    }
    mailbox.drain(maindevice).await?;
    mailbox.send(maindevice, request, timeout).await?;
    loop {
        let (_, data) = mailbox.receive(maindevice, timeout).await?;
        if take(&data)? {
            return Ok(());
        }
    }
}
