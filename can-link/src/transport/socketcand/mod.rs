//! The socketcand protocol over TCP, as a client of a daemon elsewhere ([`SocketcandClient`]) and as a
//! server that is itself the bus ([`SocketcandServer`]).
//!
//! The server speaks what socketcand speaks in raw mode and what python-can's `socketcand` interface
//! expects: `< hi >` on connect, `< ok >` to `< open CHANNEL >` (any channel name: the server is one
//! bus) and to `< rawmode >`, then `< frame … >` for every frame of the bus. A frame one client sends
//! reaches the node and every other client in raw mode. Commands it does not offer (BCM jobs, the
//! control and ISO-TP modes) are answered `< error … >` and the session goes on; malformed input is
//! answered the same way, never with a dropped connection.
//!
//! Choices:
//! - A client gets every frame from the moment its `< rawmode >` is acknowledged, but the frames are
//!   held back until the client has sent its next bytes or [`RAW_MODE_SETTLE`] has passed: python-can
//!   reads the acknowledgement with one `recv` and compares it with `< ok >` to the letter, so a frame
//!   in the same TCP segment would fail its handshake.
//! - Each client has its own writer with a queue of [`CLIENT_QUEUE`] elements; a client that does not
//!   read loses the frames that do not fit, as a CAN controller's receive queue overflows, and the bus
//!   goes on for everyone else. At most [`MAX_CLIENTS`] clients at once; when they are all there, a new
//!   client takes the place of the oldest one that has not opened a channel (a silent connection
//!   cannot lock the others out), and a client that opens none within [`OPEN_DEADLINE`] is closed.
//!   A client that takes none of what the server writes for [`STALL_TIMEOUT`] is closed too.
//! - Each client may put [`CLIENT_FRAME_RATE`] frames a second on the bus (with a burst of
//!   [`CLIENT_FRAME_BURST`]), about what one 1 Mbit/s CAN bus carries; beyond that its input is read
//!   more slowly and TCP holds it back. No client can flood the node or the others, and the node's
//!   heartbeat, SYNC and PDOs keep their instants.
//! - Answers never amplify input: a client's `< error … >` answers total at most [`ERROR_ALLOWANCE`]
//!   bytes plus a quarter of what it sent, each text escaped to printable ASCII; a run of stray bytes
//!   is one error; drops are logged at powers of two.

pub mod codec;

use std::collections::VecDeque;
use std::io::{ErrorKind, Read, Write};
use std::net::{Shutdown, SocketAddr, TcpListener, TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender, TrySendError};
use std::sync::{Arc, Mutex, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant, SystemTime};

use codec::{frame_element, Command, Message, Splitter};

use super::{BusError, BusEvent, CanBus, DropCount};
use crate::frame::CanFrame;

/// Elements queued for one client at most.
pub const CLIENT_QUEUE: usize = 8192;
/// Clients served at once at most.
pub const MAX_CLIENTS: usize = 32;
/// How long frames wait behind the `< rawmode >` acknowledgement for the client to speak first.
pub const RAW_MODE_SETTLE: Duration = Duration::from_millis(50);
/// How long the client waits for each handshake answer.
pub const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(5);
/// Error answers a client gets at most: this many bytes plus a quarter of what it sent (a flood of
/// bad input is answered with less than it sends).
pub const ERROR_ALLOWANCE: u64 = 4096;
/// How long a connected client has to open a channel before the server closes it.
pub const OPEN_DEADLINE: Duration = Duration::from_secs(10);
/// Frames one client may put on the bus per second, on average: about what a 1 Mbit/s CAN bus
/// carries (an 8-byte frame with an 11-bit identifier is 111 bits with its interframe space, at
/// most 9,009 frames/s before bit stuffing). A client that sends faster is read more slowly, so TCP
/// holds it back; the node and the other clients are not flooded by one client.
pub const CLIENT_FRAME_RATE: u32 = 10_000;
/// Frames a client may send at once above [`CLIENT_FRAME_RATE`] (an SDO block of 127 segments fits
/// several times over).
pub const CLIENT_FRAME_BURST: u32 = 1_000;
/// How long a client's connection may take none of what the server writes to it before the server
/// closes it: a client that stopped reading gives its place back.
pub const STALL_TIMEOUT: Duration = Duration::from_secs(10);

/// Frames received from clients and not yet taken by the node, at most.
const NODE_QUEUE: usize = 8192;

/// One connected client, as the server's shared state sees it.
struct Peer {
    id: u64,
    tx: SyncSender<Out>,
    raw: bool,
    dropped: DropCount,
    /// A channel is open (the handshake is done).
    opened: bool,
    /// The connection, to close it from outside its threads.
    stream: TcpStream,
}

/// What a client's writer sends.
enum Out {
    /// An element.
    Text(Arc<str>),
    /// `< ok >` to `< rawmode >`, after which the writer waits for the client to speak (or for
    /// [`RAW_MODE_SETTLE`]) before the frames follow.
    RawAck,
}

#[derive(Default)]
struct Peers {
    list: Vec<Peer>,
}

impl Peers {
    /// Queues `element` for every client in raw mode but `from`.
    fn broadcast(&mut self, from: u64, element: &Arc<str>) {
        for p in self.list.iter_mut() {
            if p.id == from || !p.raw {
                continue;
            }
            if let Err(TrySendError::Full(_)) = p.tx.try_send(Out::Text(Arc::clone(element))) {
                if let Some(n) = p.dropped.add() {
                    tracing::warn!(
                        client = p.id,
                        dropped = n,
                        "socketcand client does not read: frames dropped"
                    );
                }
            }
        }
    }

    fn reply(&self, id: u64, element: &str) {
        if let Some(p) = self.list.iter().find(|p| p.id == id) {
            let _ = p.tx.try_send(Out::Text(Arc::from(element)));
        }
    }
}

struct Shared {
    peers: Mutex<Peers>,
    to_node: SyncSender<super::Queued>,
    stop: AtomicBool,
    next_id: AtomicU64,
    /// Frames from clients dropped because the node's queue was full.
    dropped_to_node: Mutex<DropCount>,
}

impl Shared {
    fn peers(&self) -> std::sync::MutexGuard<'_, Peers> {
        self.peers.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// A socketcand server that is the bus: the node on one side, TCP clients on the other.
pub struct SocketcandServer {
    shared: Arc<Shared>,
    from_clients: Receiver<super::Queued>,
    addr: SocketAddr,
    accept: Option<JoinHandle<()>>,
}

impl SocketcandServer {
    /// Binds `addr` (`127.0.0.1:29536`; port 0 picks a free one) and starts accepting clients.
    pub fn bind(addr: SocketAddr) -> Result<SocketcandServer, BusError> {
        let what = format!("socketcand-listen:{addr}");
        let listener = TcpListener::bind(addr).map_err(|source| BusError::Open {
            what: what.clone(),
            source,
        })?;
        let addr = listener.local_addr().map_err(|source| BusError::Open {
            what: what.clone(),
            source,
        })?;
        listener
            .set_nonblocking(true)
            .map_err(|source| BusError::Open { what, source })?;
        let (to_node, from_clients) = mpsc::sync_channel(NODE_QUEUE);
        let shared = Arc::new(Shared {
            peers: Mutex::new(Peers::default()),
            to_node,
            stop: AtomicBool::new(false),
            next_id: AtomicU64::new(1),
            dropped_to_node: Mutex::new(DropCount::default()),
        });
        let s = Arc::clone(&shared);
        let accept = std::thread::Builder::new()
            .name("socketcand-accept".into())
            .spawn(move || accept_loop(&listener, &s))
            .map_err(|source| BusError::Open {
                what: format!("socketcand-listen:{addr}"),
                source,
            })?;
        Ok(SocketcandServer {
            shared,
            from_clients,
            addr,
            accept: Some(accept),
        })
    }

    /// The address the server listens on.
    pub fn local_addr(&self) -> SocketAddr {
        self.addr
    }

    /// Clients connected now.
    pub fn clients(&self) -> usize {
        self.shared.peers().list.len()
    }
}

impl Drop for SocketcandServer {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(h) = self.accept.take() {
            let _ = h.join();
        }
    }
}

impl CanBus for SocketcandServer {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        let element: Arc<str> = Arc::from(frame_element(frame, SystemTime::now()));
        self.shared.peers().broadcast(0, &element);
        Ok(())
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        super::recv_queued(&self.from_clients, timeout, || self.describe())
    }

    fn describe(&self) -> String {
        format!("socketcand-listen:{}", self.addr)
    }

    fn listen_addr(&self) -> Option<SocketAddr> {
        Some(self.addr)
    }
}

fn accept_loop(listener: &TcpListener, shared: &Arc<Shared>) {
    while !shared.stop.load(Ordering::Relaxed) {
        match listener.accept() {
            Ok((stream, peer)) => {
                if let Err(e) = serve(stream, peer, shared) {
                    tracing::warn!(%peer, "socketcand client not served: {e}");
                }
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                std::thread::sleep(Duration::from_millis(20));
            }
            Err(e) => {
                tracing::warn!("socketcand accept: {e}");
                std::thread::sleep(Duration::from_millis(100));
            }
        }
    }
}

/// Starts the reader and writer threads of one client.
fn serve(stream: TcpStream, peer: SocketAddr, shared: &Arc<Shared>) -> std::io::Result<()> {
    stream.set_nonblocking(false)?;
    stream.set_nodelay(true)?;
    {
        let mut peers = shared.peers();
        if peers.list.len() >= MAX_CLIENTS {
            // The oldest client without a channel makes room; with every client in session, the new
            // one is refused.
            match peers.list.iter().position(|p| !p.opened) {
                Some(k) => {
                    let silent = peers.list.remove(k);
                    let _ = silent.stream.shutdown(Shutdown::Both);
                    tracing::info!(
                        client = silent.id,
                        "socketcand client without a channel closed for a new one"
                    );
                }
                None => {
                    drop(peers);
                    let mut s = stream;
                    let _ = s.write_all(b"< error too many clients >");
                    let _ = s.shutdown(Shutdown::Both);
                    return Ok(());
                }
            }
        }
    }
    let id = shared.next_id.fetch_add(1, Ordering::Relaxed);
    let (tx, rx) = mpsc::sync_channel::<Out>(CLIENT_QUEUE);
    let (spoke_tx, spoke_rx) = mpsc::sync_channel::<()>(1);
    let writer_stream = stream.try_clone()?;
    // "< hi >" goes out as the first element, on its own.
    tx.try_send(Out::Text(Arc::from(Message::Hi.emit().as_str())))
        .map_err(|_| std::io::Error::other("client queue"))?;
    shared.peers().list.push(Peer {
        id,
        tx,
        raw: false,
        dropped: DropCount::default(),
        opened: false,
        stream: stream.try_clone()?,
    });
    tracing::info!(%peer, client = id, "socketcand client connected");
    std::thread::Builder::new()
        .name(format!("socketcand-tx-{id}"))
        .spawn(move || write_loop(writer_stream, &rx, &spoke_rx))?;
    let s = Arc::clone(shared);
    std::thread::Builder::new()
        .name(format!("socketcand-rx-{id}"))
        .spawn(move || {
            read_loop(stream, id, &s, &spoke_tx);
            s.peers().list.retain(|p| p.id != id);
            tracing::info!(%peer, client = id, "socketcand client gone");
        })?;
    Ok(())
}

/// A token bucket of frames: [`CLIENT_FRAME_RATE`] a second, at most [`CLIENT_FRAME_BURST`] saved.
#[derive(Debug)]
struct SendBudget {
    /// Frames that may be sent now, in millionths of a frame.
    micro: u64,
    last: Instant,
}

impl SendBudget {
    const FULL: u64 = CLIENT_FRAME_BURST as u64 * 1_000_000;

    fn new(now: Instant) -> SendBudget {
        SendBudget {
            micro: Self::FULL,
            last: now,
        }
    }

    /// Takes one frame at `now`; `None` when it may go, else how long to wait first (for a batch of
    /// 64 frames, so that a client at the limit is not woken for each frame).
    fn take(&mut self, now: Instant) -> Option<Duration> {
        let dt = now.saturating_duration_since(self.last);
        self.last = self.last.max(now);
        let earned = dt.as_micros() as u64 * u64::from(CLIENT_FRAME_RATE);
        self.micro = self.micro.saturating_add(earned).min(Self::FULL);
        if self.micro >= 1_000_000 {
            self.micro -= 1_000_000;
            return None;
        }
        let want = 64 * 1_000_000 - self.micro;
        Some(Duration::from_micros(
            want.div_ceil(u64::from(CLIENT_FRAME_RATE)),
        ))
    }
}

fn write_loop(mut stream: TcpStream, rx: &Receiver<Out>, spoke: &Receiver<()>) {
    // A client that takes nothing for this long has stopped reading: the write fails and the
    // connection closes.
    let _ = stream.set_write_timeout(Some(STALL_TIMEOUT));
    let mut batch = String::new();
    let mut next: Option<Out> = None;
    loop {
        let out = match next.take() {
            Some(o) => o,
            None => match rx.recv() {
                Ok(o) => o,
                Err(_) => break,
            },
        };
        let written = match out {
            Out::RawAck => stream.write_all(Message::Ok.emit().as_bytes()).map(|()| {
                let _ = spoke.recv_timeout(RAW_MODE_SETTLE);
            }),
            Out::Text(t) => {
                batch.clear();
                batch.push_str(&t);
                // Frames already queued go out together; a handshake answer goes out alone.
                while t.starts_with("< frame") && batch.len() < 16 * 1024 {
                    match rx.try_recv() {
                        Ok(Out::Text(n)) if n.starts_with("< frame") => batch.push_str(&n),
                        Ok(other) => {
                            next = Some(other);
                            break;
                        }
                        Err(_) => break,
                    }
                }
                stream.write_all(batch.as_bytes())
            }
        };
        if written.is_err() {
            break;
        }
    }
    let _ = stream.shutdown(Shutdown::Both);
}

fn read_loop(mut stream: TcpStream, id: u64, shared: &Shared, spoke: &SyncSender<()>) {
    let _ = stream.set_read_timeout(Some(Duration::from_millis(100)));
    let mut splitter = Splitter::new();
    let mut buf = [0u8; 4096];
    let mut opened = false;
    let mut raw = false;
    let connected = Instant::now();
    let mut budget = SendBudget::new(connected);
    // No amplification: bytes received and error bytes answered.
    let (mut received, mut answered) = (0u64, 0u64);
    while !shared.stop.load(Ordering::Relaxed) {
        if !opened && connected.elapsed() >= OPEN_DEADLINE {
            let text = Message::Error("no channel opened in time".into()).emit();
            // Queued before the peer goes: its writer sends it, then closes the connection.
            shared.peers().reply(id, &text);
            return;
        }
        let n = match stream.read(&mut buf) {
            Ok(0) => return,
            Ok(n) => n,
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => continue,
            Err(e) if e.kind() == ErrorKind::Interrupted => continue,
            Err(_) => return,
        };
        received += n as u64;
        splitter.push(&buf[..n]);
        while let Some(element) = splitter.next_element() {
            // Whatever the client says after `< rawmode >` shows it has read the acknowledgement.
            if raw {
                let _ = spoke.try_send(());
            }
            let answer = match element.map(|e| Command::parse(&e)) {
                Err(e) | Ok(Err(e)) => Some(Message::Error(e.to_string())),
                Ok(Ok(c)) => {
                    if matches!(c, Command::Send(_)) {
                        // Beyond its budget the client waits here, unread (TCP holds it back).
                        while let Some(wait) = budget.take(Instant::now()) {
                            if shared.stop.load(Ordering::Relaxed) {
                                return;
                            }
                            std::thread::sleep(wait);
                        }
                    }
                    if opened {
                        match c {
                            Command::RawMode => raw = true,
                            Command::BcmMode => raw = false,
                            _ => {}
                        }
                    }
                    handle(c, id, &mut opened, shared)
                }
            };
            match answer {
                Some(a @ Message::Error(_)) => {
                    let text = a.emit();
                    if answered + text.len() as u64 <= ERROR_ALLOWANCE + received / 4 {
                        answered += text.len() as u64;
                        shared.peers().reply(id, &text);
                    }
                }
                Some(a) => shared.peers().reply(id, &a.emit()),
                None => {}
            }
        }
    }
}

/// Acts on one command; the answer to send back, if any.
fn handle(command: Command, id: u64, opened: &mut bool, shared: &Shared) -> Option<Message> {
    match command {
        Command::Open(channel) if !*opened => {
            tracing::debug!(client = id, channel, "socketcand open");
            *opened = true;
            if let Some(p) = shared.peers().list.iter_mut().find(|p| p.id == id) {
                p.opened = true;
            }
            Some(Message::Ok)
        }
        Command::Open(_) => Some(Message::Error("a channel is open already".into())),
        Command::RawMode | Command::BcmMode if !*opened => {
            Some(Message::Error("open a channel first".into()))
        }
        Command::RawMode => {
            let mut peers = shared.peers();
            // The acknowledgement is queued before the first frame can be.
            if let Some(p) = peers.list.iter_mut().find(|p| p.id == id) {
                let _ = p.tx.try_send(Out::RawAck);
                p.raw = true;
            }
            None
        }
        Command::BcmMode => {
            if let Some(p) = shared.peers().list.iter_mut().find(|p| p.id == id) {
                p.raw = false;
            }
            Some(Message::Ok)
        }
        Command::OtherMode(m) => Some(Message::Error(format!("{m} is not offered"))),
        Command::Echo => Some(Message::Echo),
        Command::Send(_) if !*opened => Some(Message::Error("open a channel first".into())),
        Command::Send(frame) => {
            let at = SystemTime::now();
            let element: Arc<str> = Arc::from(frame_element(&frame, at));
            shared.peers().broadcast(id, &element);
            if shared
                .to_node
                .try_send((frame, at, Instant::now()))
                .is_err()
            {
                let logged = shared
                    .dropped_to_node
                    .lock()
                    .unwrap_or_else(PoisonError::into_inner)
                    .add();
                if let Some(n) = logged {
                    tracing::warn!(
                        client = id,
                        dropped = n,
                        "node receive queue full: frames dropped"
                    );
                }
            }
            None
        }
        Command::Unsupported(w) if w.is_empty() => Some(Message::Error("empty element".into())),
        Command::Unsupported(w) => Some(Message::Error(format!("{w} is not offered"))),
    }
}

/// A client of a socketcand daemon, in raw mode on one channel.
pub struct SocketcandClient {
    stream: TcpStream,
    splitter: Splitter,
    pending: VecDeque<BusEvent>,
    name: String,
}

impl SocketcandClient {
    /// Connects to `host:port`, opens `channel` and switches to raw mode.
    pub fn connect(host: &str, port: u16, channel: &str) -> Result<SocketcandClient, BusError> {
        let name = if host.contains(':') {
            format!("socketcand://[{host}]:{port}/{channel}")
        } else {
            format!("socketcand://{host}:{port}/{channel}")
        };
        let open_error = |source| BusError::Open {
            what: name.clone(),
            source,
        };
        let addrs: Vec<SocketAddr> = (host, port)
            .to_socket_addrs()
            .map_err(open_error)?
            .collect();
        let mut last = std::io::Error::new(ErrorKind::NotFound, "no address for the host");
        let mut stream = None;
        for a in addrs {
            match TcpStream::connect_timeout(&a, HANDSHAKE_TIMEOUT) {
                Ok(s) => {
                    stream = Some(s);
                    break;
                }
                Err(e) => last = e,
            }
        }
        let stream = stream.ok_or_else(|| open_error(last))?;
        stream.set_nodelay(true).map_err(open_error)?;
        let mut client = SocketcandClient {
            stream,
            splitter: Splitter::new(),
            pending: VecDeque::new(),
            name,
        };
        client.expect(&Message::Hi, "the greeting")?;
        client.command(&Command::Open(channel.to_string()))?;
        client.expect(&Message::Ok, &format!("open {channel}"))?;
        client.command(&Command::RawMode)?;
        client.expect(&Message::Ok, "rawmode")?;
        Ok(client)
    }

    fn command(&mut self, c: &Command) -> Result<(), BusError> {
        self.stream
            .write_all(c.emit().as_bytes())
            .map_err(|source| BusError::Io {
                what: self.name.clone(),
                source,
            })
    }

    /// Waits for the handshake answer `want`; an `< error … >` or anything else is a protocol error.
    fn expect(&mut self, want: &Message, step: &str) -> Result<(), BusError> {
        let deadline = Instant::now() + HANDSHAKE_TIMEOUT;
        loop {
            if let Some(element) = self.splitter.next_element() {
                let got = element
                    .map_err(|e| e.to_string())
                    .and_then(|e| Message::parse(&e).map_err(|e| e.to_string()));
                return match got {
                    Ok(m) if &m == want => Ok(()),
                    Ok(Message::Error(text)) => Err(self.protocol(format!("{step}: {text}"))),
                    Ok(m) => Err(self.protocol(format!(
                        "{step}: expected {}, got {}",
                        want.emit(),
                        m.emit()
                    ))),
                    Err(e) => Err(self.protocol(format!("{step}: {e}"))),
                };
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Err(self.protocol(format!("{step}: no answer within 5 s")));
            }
            self.fill(left)?;
        }
    }

    fn protocol(&self, detail: String) -> BusError {
        BusError::Protocol {
            what: self.name.clone(),
            detail,
        }
    }

    /// Reads what arrives within `timeout` into the splitter; false when nothing came.
    fn fill(&mut self, timeout: Duration) -> Result<bool, BusError> {
        let _ = self
            .stream
            .set_read_timeout(Some(timeout.max(Duration::from_millis(1))));
        let mut buf = [0u8; 4096];
        match self.stream.read(&mut buf) {
            Ok(0) => Err(BusError::Closed(self.name.clone())),
            Ok(n) => {
                self.splitter.push(&buf[..n]);
                Ok(true)
            }
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => Ok(false),
            Err(e) if e.kind() == ErrorKind::Interrupted => Ok(false),
            Err(source) => Err(BusError::Io {
                what: self.name.clone(),
                source,
            }),
        }
    }

    fn drain_elements(&mut self) {
        while let Some(element) = self.splitter.next_element() {
            let event = match element.map(|e| Message::parse(&e)) {
                Ok(Ok(Message::Frame { frame, at })) => BusEvent::Frame {
                    frame,
                    at,
                    received: Instant::now(),
                },
                Ok(Ok(Message::Error(text))) => BusEvent::Error(format!("socketcand: {text}")),
                Ok(Ok(_)) => continue,
                Err(e) | Ok(Err(e)) => BusEvent::Error(format!("socketcand: {e}")),
            };
            self.pending.push_back(event);
        }
    }
}

impl CanBus for SocketcandClient {
    fn send(&mut self, frame: &CanFrame) -> Result<(), BusError> {
        if frame.is_rtr() {
            return Err(self.protocol(format!(
                "{frame}: socketcand's raw mode carries no remote frames"
            )));
        }
        self.command(&Command::Send(*frame))
    }

    fn recv(&mut self, timeout: Duration) -> Result<Option<BusEvent>, BusError> {
        let deadline = Instant::now() + timeout;
        loop {
            self.drain_elements();
            if let Some(e) = self.pending.pop_front() {
                return Ok(Some(e));
            }
            let left = deadline.saturating_duration_since(Instant::now());
            if left.is_zero() {
                return Ok(None);
            }
            self.fill(left)?;
        }
    }

    fn describe(&self) -> String {
        self.name.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(id: u16, data: &[u8]) -> CanFrame {
        CanFrame::new(id, data).unwrap()
    }

    fn server() -> SocketcandServer {
        SocketcandServer::bind("127.0.0.1:0".parse().unwrap()).unwrap()
    }

    fn next_frame(bus: &mut dyn CanBus) -> CanFrame {
        let end = Instant::now() + Duration::from_secs(5);
        while Instant::now() < end {
            if let Some(BusEvent::Frame { frame, .. }) =
                bus.recv(Duration::from_millis(100)).unwrap()
            {
                return frame;
            }
        }
        panic!("no frame within 5 s");
    }

    fn connect(s: &SocketcandServer) -> SocketcandClient {
        let c = SocketcandClient::connect("127.0.0.1", s.local_addr().port(), "can0").unwrap();
        std::thread::sleep(RAW_MODE_SETTLE + Duration::from_millis(20));
        c
    }

    #[test]
    fn node_and_clients_share_one_bus() {
        let mut s = server();
        let mut a = connect(&s);
        let mut b = connect(&s);
        assert_eq!(s.clients(), 2);
        // A client's frame reaches the node and the other client, not itself.
        let req = f(0x605, &[0x40, 0x18, 0x10, 1, 0, 0, 0, 0]);
        a.send(&req).unwrap();
        assert_eq!(next_frame(&mut s), req);
        assert_eq!(next_frame(&mut b), req);
        assert!(a.recv(Duration::from_millis(100)).unwrap().is_none());
        // The node's frame reaches both clients.
        let resp = f(0x585, &[0x43, 0x18, 0x10, 1, 4, 0, 0, 0]);
        s.send(&resp).unwrap();
        assert_eq!(next_frame(&mut a), resp);
        assert_eq!(next_frame(&mut b), resp);
        drop(a);
        let end = Instant::now() + Duration::from_secs(2);
        while s.clients() != 1 && Instant::now() < end {
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(s.clients(), 1);
    }

    #[test]
    fn python_can_handshake_to_the_byte() {
        let mut s = server();
        let mut t = TcpStream::connect(s.local_addr()).unwrap();
        t.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let read = |t: &mut TcpStream| {
            let mut buf = [0u8; 256];
            let n = t.read(&mut buf).unwrap();
            String::from_utf8_lossy(&buf[..n]).into_owned()
        };
        assert_eq!(read(&mut t), "< hi >");
        t.write_all(b"< open vcan7 >").unwrap();
        assert_eq!(read(&mut t), "< ok >");
        // Frames of the node right now must not join the acknowledgement, nor be lost.
        t.write_all(b"< rawmode >").unwrap();
        std::thread::sleep(Duration::from_millis(5));
        for _ in 0..20 {
            s.send(&f(0x701, &[0x7F])).unwrap();
        }
        std::thread::sleep(Duration::from_millis(5));
        assert_eq!(read(&mut t), "< ok >");
        t.write_all(b"< echo >").unwrap();
        let mut text = String::new();
        while text.matches("< frame 701 ").count() < 20 || !text.contains("< echo >") {
            text.push_str(&read(&mut t));
        }
        assert_eq!(text.matches(" 7F >").count(), 20, "{text}");
        // python-can's spelling of a send: lower-case, unpadded, DLC in hex.
        t.write_all(b"< send 605 8 2f 17 10 0 64 0 0 0 >").unwrap();
        assert_eq!(
            next_frame(&mut s),
            f(0x605, &[0x2F, 0x17, 0x10, 0, 0x64, 0, 0, 0])
        );
    }

    #[test]
    fn bad_input_is_answered_and_the_session_goes_on() {
        let mut s = server();
        let mut t = TcpStream::connect(s.local_addr()).unwrap();
        t.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let mut got = String::new();
        let mut read_until = |t: &mut TcpStream, want: &str| {
            let mut buf = [0u8; 1024];
            while !got.contains(want) {
                let n = t.read(&mut buf).unwrap();
                assert!(n > 0, "closed; got {got:?}");
                got.push_str(&String::from_utf8_lossy(&buf[..n]));
            }
        };
        t.write_all(b"< send 605 0 >").unwrap();
        read_until(&mut t, "< error open a channel first >");
        t.write_all(b"< open can0 >< send 800 0 >").unwrap();
        read_until(&mut t, "identifier 800 is above 7FF");
        t.write_all(b"garbage< add 1 0 123 0 >").unwrap();
        read_until(&mut t, "add is not offered");
        t.write_all(&[b'<'; 600]).unwrap();
        t.write_all(b"> < echo >").unwrap();
        read_until(&mut t, "< echo >");
        t.write_all(b"< send 123 1 AB >").unwrap();
        assert_eq!(next_frame(&mut s), f(0x123, &[0xAB]));
    }

    /// More silent connections than [`MAX_CLIENTS`] cannot lock a client out: a new client takes the
    /// place of the oldest one without a channel, and its handshake is answered at once (within a
    /// second on a busy machine); clients in session keep theirs.
    #[test]
    fn silent_connections_do_not_lock_clients_out() {
        let mut s = server();
        let mut session = connect(&s);
        let silent: Vec<TcpStream> = (0..MAX_CLIENTS + 8)
            .map(|_| TcpStream::connect(s.local_addr()).unwrap())
            .collect();
        std::thread::sleep(Duration::from_millis(300));
        let started = Instant::now();
        let mut probe = SocketcandClient::connect("127.0.0.1", s.local_addr().port(), "can0")
            .expect("served despite the silent connections");
        assert!(
            started.elapsed() < Duration::from_secs(1),
            "{:?}",
            started.elapsed()
        );
        std::thread::sleep(RAW_MODE_SETTLE + Duration::from_millis(20));
        // Both sessions are on the bus.
        probe.send(&f(0x123, &[1])).unwrap();
        assert_eq!(next_frame(&mut s), f(0x123, &[1]));
        assert_eq!(next_frame(&mut session), f(0x123, &[1]));
        assert!(s.clients() <= MAX_CLIENTS, "{}", s.clients());
        drop(silent);
    }

    /// The send budget: [`CLIENT_FRAME_BURST`] frames at once, then [`CLIENT_FRAME_RATE`] a second
    /// (10 frames a millisecond), a wait for 64 frames (6.4 ms) when it is spent; time going back
    /// earns nothing and idle time saves no more than the burst.
    #[test]
    fn the_send_budget_is_10000_frames_a_second_after_a_burst_of_1000() {
        let t0 = Instant::now();
        let mut b = SendBudget::new(t0);
        for k in 0..1000 {
            assert_eq!(b.take(t0), None, "frame {k} of the burst");
        }
        assert_eq!(b.take(t0), Some(Duration::from_micros(6400)));
        let t1 = t0 + Duration::from_millis(1);
        for k in 0..10 {
            assert_eq!(b.take(t1), None, "frame {k} of the millisecond");
        }
        assert_eq!(b.take(t1), Some(Duration::from_micros(6400)));
        assert_eq!(
            b.take(t0),
            Some(Duration::from_micros(6400)),
            "earlier time"
        );
        // 100 µs more: one frame; then 64 frames need 6.4 ms less the 0 µs saved.
        let t2 = t1 + Duration::from_micros(100);
        assert_eq!(b.take(t2), None);
        assert_eq!(b.take(t2), Some(Duration::from_micros(6400)));
        // 50 µs: half a frame saved, the wait is for the other 63.5.
        let t3 = t2 + Duration::from_micros(50);
        assert_eq!(b.take(t3), Some(Duration::from_micros(6350)));
        let t4 = t3 + Duration::from_secs(10);
        for k in 0..1000 {
            assert_eq!(b.take(t4), None, "frame {k} after 10 s idle");
        }
        assert!(b.take(t4).is_some(), "no more than the burst saved");
    }

    /// A client that sends faster than [`CLIENT_FRAME_RATE`] is held back: 3,000 frames written at
    /// once reach the node in no less than the time the 2,000 beyond the burst take at the rate
    /// (200 ms), all of them, in order.
    #[test]
    fn a_client_beyond_its_budget_is_held_back_not_dropped() {
        let mut s = server();
        let mut t = TcpStream::connect(s.local_addr()).unwrap();
        t.write_all(b"< open can0 >< rawmode >").unwrap();
        let text: String = (0..3000u32)
            .map(|k| format!("< send 123 2 {:02X} {:02X} >", k & 0xFF, k >> 8))
            .collect();
        let started = Instant::now();
        t.write_all(text.as_bytes()).unwrap();
        for k in 0..3000u32 {
            assert_eq!(
                next_frame(&mut s),
                f(0x123, &[(k & 0xFF) as u8, (k >> 8) as u8]),
                "frame {k}"
            );
        }
        assert!(
            started.elapsed() >= Duration::from_millis(200),
            "{:?}",
            started.elapsed()
        );
    }

    /// A client in session that takes none of what is written to it for [`STALL_TIMEOUT`] is closed;
    /// one that reads stays.
    #[test]
    fn a_client_that_stops_reading_is_closed_after_the_stall_timeout() {
        let mut s = server();
        let stalled = connect(&s);
        let mut reader = connect(&s);
        let stop = Arc::new(AtomicBool::new(false));
        let st = Arc::clone(&stop);
        let drain = std::thread::spawn(move || {
            let mut n = 0u64;
            while !st.load(Ordering::Relaxed) {
                if let Ok(Some(BusEvent::Frame { .. })) = reader.recv(Duration::from_millis(10)) {
                    n += 1;
                }
            }
            (reader, n)
        });
        let started = Instant::now();
        let frame = f(0x181, &[0xA5; 8]);
        while s.clients() == 2 && started.elapsed() < STALL_TIMEOUT * 4 {
            for _ in 0..200 {
                s.send(&frame).unwrap();
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let closed_after = started.elapsed();
        stop.store(true, Ordering::Relaxed);
        let (_reader, read) = drain.join().unwrap();
        assert_eq!(s.clients(), 1, "after {closed_after:?}");
        assert!(
            closed_after >= STALL_TIMEOUT,
            "closed after {closed_after:?}"
        );
        assert!(read > 0);
        drop(stalled);
    }

    /// A client that opens no channel within [`OPEN_DEADLINE`] is told so and closed (not before).
    #[test]
    fn a_client_without_a_channel_is_closed_after_the_deadline() {
        let s = server();
        let mut t = TcpStream::connect(s.local_addr()).unwrap();
        t.set_read_timeout(Some(OPEN_DEADLINE * 3)).unwrap();
        let started = Instant::now();
        let mut got = Vec::new();
        let mut buf = [0u8; 256];
        loop {
            match t.read(&mut buf) {
                Ok(0) | Err(_) => break,
                Ok(n) => got.extend_from_slice(&buf[..n]),
            }
        }
        assert!(
            started.elapsed() >= OPEN_DEADLINE,
            "{:?}",
            started.elapsed()
        );
        assert_eq!(
            String::from_utf8_lossy(&got),
            "< hi >< error no channel opened in time >"
        );
    }

    /// A flood of bad input gets less back than it sends: at most [`ERROR_ALLOWANCE`] bytes of
    /// errors plus a quarter of the input, and the session goes on.
    #[test]
    fn bad_input_is_not_amplified() {
        let s = server();
        let mut t = TcpStream::connect(s.local_addr()).unwrap();
        t.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
        let reader = {
            let mut t = t.try_clone().unwrap();
            std::thread::spawn(move || {
                let mut got = Vec::new();
                let mut buf = [0u8; 65536];
                while !got.ends_with(b"< echo >") {
                    match t.read(&mut buf) {
                        Ok(0) | Err(_) => break,
                        Ok(n) => got.extend_from_slice(&buf[..n]),
                    }
                }
                got
            })
        };
        t.write_all(b"< open can0 >").unwrap();
        let junk: Vec<u8> = b"<x>".repeat(100_000);
        t.write_all(&junk).unwrap();
        t.write_all(b"< echo >").unwrap();
        let got = reader.join().unwrap();
        assert!(got.ends_with(b"< echo >"), "the session goes on");
        let limit =
            ERROR_ALLOWANCE as usize + (13 + junk.len() + 8) / 4 + b"< hi >< ok >< echo >".len();
        assert!(
            got.len() <= limit,
            "{} bytes back for {} sent",
            got.len(),
            junk.len()
        );
        assert!(got.is_ascii());
    }

    #[test]
    fn client_reports_a_refused_open() {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = l.local_addr().unwrap().port();
        let h = std::thread::spawn(move || {
            let (mut t, _) = l.accept().unwrap();
            t.write_all(b"< hi >").unwrap();
            let mut buf = [0u8; 64];
            let _ = t.read(&mut buf).unwrap();
            t.write_all(b"< error could not open bus >").unwrap();
            std::thread::sleep(Duration::from_millis(100));
        });
        let Err(e) = SocketcandClient::connect("127.0.0.1", port, "can9") else {
            panic!("a refused open connected")
        };
        assert_eq!(
            e.to_string(),
            format!(
                "socketcand://127.0.0.1:{port}/can9: protocol error: open can9: could not open bus"
            )
        );
        h.join().unwrap();
    }

    #[test]
    fn a_client_that_does_not_read_does_not_stop_the_bus() {
        const FRAMES: u32 = 4 * CLIENT_QUEUE as u32;
        let mut s = server();
        let mut slow = TcpStream::connect(s.local_addr()).unwrap();
        slow.write_all(b"< open can0 >< rawmode >").unwrap();
        let mut fast = connect(&s);
        let reader = std::thread::spawn(move || {
            let mut got = 0u32;
            let end = Instant::now() + Duration::from_secs(30);
            while got < FRAMES && Instant::now() < end {
                if let Some(BusEvent::Frame { frame, .. }) =
                    fast.recv(Duration::from_millis(100)).unwrap()
                {
                    assert_eq!(u32::from_le_bytes(frame.data().try_into().unwrap()), got);
                    got += 1;
                }
            }
            got
        });
        std::thread::sleep(RAW_MODE_SETTLE + Duration::from_millis(20));
        // Far more than the slow client's queue and its socket buffers hold.
        let started = Instant::now();
        for k in 0..FRAMES {
            s.send(&f(0x181, &k.to_le_bytes())).unwrap();
            if k % 512 == 511 {
                std::thread::sleep(Duration::from_millis(2));
            }
        }
        assert!(
            started.elapsed() < Duration::from_secs(10),
            "the node was held up"
        );
        assert_eq!(
            reader.join().unwrap(),
            FRAMES,
            "the reading client got every frame in order"
        );
        drop(slow);
    }
}
