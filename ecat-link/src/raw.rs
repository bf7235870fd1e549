//! An AF_PACKET raw socket bound to one interface for EtherType 0x88A4 (Linux): what the emulator
//! receives EtherCAT frames on and sends them back on, one at a time ([`RawSocket::recv`],
//! [`RawSocket::send`]) or several frames in one system call ([`RawSocket::recv_batch`],
//! [`RawSocket::send_batch`]: recvmmsg(2) and sendmmsg(2) over a [`Batch`]). With
//! [`RawSocket::capture_to`], every frame it receives and sends is also written to a pcapng
//! capture.

use std::ffi::CString;
use std::io;
use std::os::fd::{AsFd, AsRawFd, BorrowedFd, FromRawFd, OwnedFd, RawFd};
use std::time::{Duration, SystemTime};

use link_capture::pcapng::{Direction, LINKTYPE_ETHERNET};
use link_capture::{Capture, Interface};

use crate::ETHERTYPE;

/// Why the socket could not be opened.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RawError {
    /// The interface name.
    #[error("interface {0:?}: no such interface")]
    NoInterface(String),
    /// The interface name is not a name.
    #[error("interface {0:?}: not a valid interface name")]
    BadName(String),
    /// A system call failed.
    #[error("interface {iface}: {what}: {source}")]
    Io {
        /// The interface.
        iface: String,
        /// What was being done.
        what: &'static str,
        /// The error.
        source: io::Error,
    },
}

/// A raw socket on one interface.
#[derive(Debug)]
pub struct RawSocket {
    fd: OwnedFd,
    iface: String,
    /// Where the frames received and sent are written too.
    capture: Option<Interface>,
}

fn check(r: libc::c_int) -> io::Result<libc::c_int> {
    if r < 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(r)
    }
}

/// The receive buffer a raw socket asks the kernel for: thousands of full-size frames with the
/// kernel's bookkeeping of each, against the 208 KiB default (which dropped frames under 20,000 junk
/// frames/s).
pub const RECEIVE_BUFFER: usize = 16 << 20;

impl RawSocket {
    /// Opens a raw socket on `iface` receiving EtherCAT frames, in promiscuous mode (a master may send
    /// to any destination address). Needs CAP_NET_RAW.
    pub fn open(iface: &str) -> Result<RawSocket, RawError> {
        let name = CString::new(iface).map_err(|_| RawError::BadName(iface.into()))?;
        if iface.is_empty() || iface.len() >= libc::IFNAMSIZ {
            return Err(RawError::BadName(iface.into()));
        }
        let io = |what: &'static str| {
            let iface = iface.to_string();
            move |source| RawError::Io {
                iface,
                what,
                source,
            }
        };
        // SAFETY: a plain C call with a NUL-terminated name.
        let index = unsafe { libc::if_nametoindex(name.as_ptr()) };
        if index == 0 {
            return Err(RawError::NoInterface(iface.into()));
        }
        let proto = ETHERTYPE.to_be();
        // Protocol 0: the socket takes no frame until bind(2) gives it the interface and the
        // EtherType (packet(7)). Opened with the EtherType, it would take the EtherCAT frames of
        // every interface until then, and a frame of another link (another master's, with the same
        // frame index) would wait in it to be taken for an answer.
        // SAFETY: socket(2) with constant arguments; the descriptor is owned at once.
        let fd = check(unsafe {
            libc::socket(
                libc::AF_PACKET,
                libc::SOCK_RAW | libc::SOCK_NONBLOCK | libc::SOCK_CLOEXEC,
                0,
            )
        })
        .map_err(io("opening a raw socket"))?;
        // SAFETY: `fd` is a fresh descriptor nobody else owns.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        // SAFETY: sockaddr_ll is plain data; all-zero is a valid value.
        let mut addr: libc::sockaddr_ll = unsafe { std::mem::zeroed() };
        addr.sll_family = libc::AF_PACKET as u16;
        addr.sll_protocol = proto;
        addr.sll_ifindex = index as i32;
        // SAFETY: `addr` is a valid sockaddr_ll of the size passed.
        check(unsafe {
            libc::bind(
                fd.as_raw_fd(),
                &addr as *const libc::sockaddr_ll as *const libc::sockaddr,
                std::mem::size_of::<libc::sockaddr_ll>() as u32,
            )
        })
        .map_err(io("binding the raw socket"))?;
        // SAFETY: packet_mreq is plain data.
        let mut mreq: libc::packet_mreq = unsafe { std::mem::zeroed() };
        mreq.mr_ifindex = index as i32;
        mreq.mr_type = libc::PACKET_MR_PROMISC as u16;
        // SAFETY: `mreq` is a valid packet_mreq of the size passed.
        check(unsafe {
            libc::setsockopt(
                fd.as_raw_fd(),
                libc::SOL_PACKET,
                libc::PACKET_ADD_MEMBERSHIP,
                &mreq as *const libc::packet_mreq as *const libc::c_void,
                std::mem::size_of::<libc::packet_mreq>() as u32,
            )
        })
        .map_err(io("switching to promiscuous mode"))?;
        // A burst of frames (a master's, or junk on the link) waits in the kernel rather than being
        // dropped there: SO_RCVBUFFORCE goes past rmem_max with CAP_NET_ADMIN, SO_RCVBUF otherwise.
        let size = RECEIVE_BUFFER as libc::c_int;
        for option in [libc::SO_RCVBUFFORCE, libc::SO_RCVBUF] {
            // SAFETY: an int option of the size passed.
            let set = unsafe {
                libc::setsockopt(
                    fd.as_raw_fd(),
                    libc::SOL_SOCKET,
                    option,
                    &size as *const libc::c_int as *const libc::c_void,
                    std::mem::size_of::<libc::c_int>() as u32,
                )
            };
            if set == 0 {
                break;
            }
        }
        // The frames this host sends are not handed back to the socket (Linux 4.20): the
        // receiver skips them anyway (PACKET_OUTGOING), and each would cost a receive.
        let ignore: libc::c_int = 1;
        // SAFETY: an int option of the size passed. Where the kernel does not know it, the
        // receiver skips this host's frames as before.
        unsafe {
            libc::setsockopt(
                fd.as_raw_fd(),
                libc::SOL_PACKET,
                libc::PACKET_IGNORE_OUTGOING,
                &ignore as *const libc::c_int as *const libc::c_void,
                std::mem::size_of::<libc::c_int>() as u32,
            )
        };
        Ok(RawSocket {
            fd,
            iface: iface.into(),
            capture: None,
        })
    }

    /// The interface.
    pub fn interface(&self) -> &str {
        &self.iface
    }

    /// Writes every frame this socket receives and sends from now on to `capture` too, whole
    /// Ethernet frames (`LINKTYPE_ETHERNET`) of an interface named as this socket's: a received
    /// one at the time it was taken from the socket, a sent one once the kernel took it. The
    /// records reach the file before each [`RawSocket::wait`], at [`RawSocket::flush_capture`]
    /// and when the socket is dropped.
    pub fn capture_to(&mut self, capture: &Capture) {
        self.capture = Some(capture.interface(&self.iface, LINKTYPE_ETHERNET));
    }

    /// Writes what the capture holds of this socket's frames so far: what a caller that waits for
    /// the socket by other means than [`RawSocket::wait`] calls before it waits.
    pub fn flush_capture(&self) {
        if let Some(c) = &self.capture {
            c.flush();
        }
    }

    /// The kernel's receive buffer of the socket in bytes (SO_RCVBUF: twice what was asked, for the
    /// kernel's bookkeeping).
    pub fn receive_buffer(&self) -> io::Result<usize> {
        let mut size: libc::c_int = 0;
        let mut len = std::mem::size_of::<libc::c_int>() as libc::socklen_t;
        // SAFETY: an int option with its length.
        check(unsafe {
            libc::getsockopt(
                self.fd.as_raw_fd(),
                libc::SOL_SOCKET,
                libc::SO_RCVBUF,
                &mut size as *mut libc::c_int as *mut libc::c_void,
                &mut len,
            )
        })?;
        Ok(usize::try_from(size).unwrap_or(0))
    }

    /// Waits until a frame can be read, at most `timeout`; true when one can.
    pub fn wait(&self, timeout: Duration) -> io::Result<bool> {
        self.flush_capture();
        let mut p = libc::pollfd {
            fd: self.fd.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        let ms = timeout.as_micros().div_ceil(1000).min(i32::MAX as u128) as i32;
        // SAFETY: one valid pollfd.
        match check(unsafe { libc::poll(&mut p, 1, ms) }) {
            Ok(n) => Ok(n > 0),
            Err(e) if e.kind() == io::ErrorKind::Interrupted => Ok(false),
            Err(e) => Err(e),
        }
    }

    /// Receives one frame that arrived on the interface (not one this host sent) into `buf`;
    /// `None` when none is waiting.
    pub fn recv(&self, buf: &mut [u8]) -> io::Result<Option<usize>> {
        loop {
            // SAFETY: sockaddr_ll is plain data.
            let mut from: libc::sockaddr_ll = unsafe { std::mem::zeroed() };
            let mut len = std::mem::size_of::<libc::sockaddr_ll>() as u32;
            // SAFETY: `buf` and `from` are valid for the lengths passed.
            let n = unsafe {
                libc::recvfrom(
                    self.fd.as_raw_fd(),
                    buf.as_mut_ptr() as *mut libc::c_void,
                    buf.len(),
                    libc::MSG_TRUNC,
                    &mut from as *mut libc::sockaddr_ll as *mut libc::sockaddr,
                    &mut len,
                )
            };
            if n < 0 {
                let e = io::Error::last_os_error();
                return match e.kind() {
                    io::ErrorKind::WouldBlock => Ok(None),
                    io::ErrorKind::Interrupted => continue,
                    _ => Err(e),
                };
            }
            if from.sll_pkttype == libc::PACKET_OUTGOING {
                continue;
            }
            // MSG_TRUNC gives the frame's real length: a longer one than the buffer is cut, and the
            // caller sees it does not parse.
            let n = (n as usize).min(buf.len());
            if let Some(c) = &self.capture {
                c.record(SystemTime::now(), Direction::Inbound, &buf[..n]);
            }
            return Ok(Some(n));
        }
    }

    /// Receives the frames waiting on the socket (not those this host sent), as many as `batch`
    /// holds, in one system call (recvmmsg(2)); `batch` then holds them in the order they arrived
    /// (a longer one than its buffer cut to it). 0 when none is waiting.
    pub fn recv_batch(&self, batch: &mut Batch) -> io::Result<usize> {
        batch.count = 0;
        let want = batch.bufs.len();
        // SAFETY: plain data; all-zero is a valid value of each.
        let mut addrs: [libc::sockaddr_ll; Batch::MAX] = unsafe { std::mem::zeroed() };
        let mut iovs: [libc::iovec; Batch::MAX] = unsafe { std::mem::zeroed() };
        let mut hdrs: [libc::mmsghdr; Batch::MAX] = unsafe { std::mem::zeroed() };
        for (k, buf) in batch.bufs.iter_mut().enumerate() {
            iovs[k].iov_base = buf.as_mut_ptr() as *mut libc::c_void;
            iovs[k].iov_len = buf.len();
            hdrs[k].msg_hdr.msg_name = &mut addrs[k] as *mut libc::sockaddr_ll as *mut _;
            hdrs[k].msg_hdr.msg_namelen = std::mem::size_of::<libc::sockaddr_ll>() as u32;
            hdrs[k].msg_hdr.msg_iov = &mut iovs[k];
            hdrs[k].msg_hdr.msg_iovlen = 1;
        }
        // SAFETY: `want` headers, each over one buffer of `batch` and one address, valid for the
        // lengths given; no timeout. (The socket does not block; a frame longer than its buffer
        // is cut to it, as `recv` cuts it.)
        let n = unsafe {
            libc::recvmmsg(
                self.fd.as_raw_fd(),
                hdrs.as_mut_ptr(),
                want as libc::c_uint,
                0,
                std::ptr::null_mut(),
            )
        };
        let Ok(n) = usize::try_from(n) else {
            let e = io::Error::last_os_error();
            return if e.kind() == io::ErrorKind::WouldBlock {
                Ok(0)
            } else {
                Err(e)
            };
        };
        for k in 0..n {
            // This host's own frames, where the kernel hands them back (before Linux 4.20): left
            // out, the others moved up. (0 when they were all this host's: the caller waits for
            // the socket again, and finds the frames still waiting.)
            if addrs[k].sll_pkttype == libc::PACKET_OUTGOING {
                continue;
            }
            let at = batch.count;
            batch.bufs.swap(at, k);
            batch.lens[at] = hdrs[k].msg_len as usize;
            batch.count += 1;
        }
        if let Some(c) = &self.capture {
            let frames = (0..batch.count).map(|k| batch.frame(k));
            c.record_all(SystemTime::now(), Direction::Inbound, frames);
        }
        Ok(batch.count)
    }

    /// Sends the frames of `batch` that are to be sent ([`Batch::skip`]), in order, in as few
    /// system calls as the kernel takes them (sendmmsg(2)). A frame the kernel refuses is left
    /// out and the others are sent; the first refusal is the error.
    pub fn send_batch(&self, batch: &Batch) -> io::Result<()> {
        // SAFETY: plain data; all-zero is a valid value of each.
        let mut iovs: [libc::iovec; Batch::MAX] = unsafe { std::mem::zeroed() };
        let mut hdrs: [libc::mmsghdr; Batch::MAX] = unsafe { std::mem::zeroed() };
        let mut n = 0;
        for k in (0..batch.count).filter(|&k| batch.lens[k] > 0) {
            // The kernel only reads the frames (sendmmsg's iovecs are shared with recvmmsg's).
            iovs[n].iov_base = batch.bufs[k].as_ptr() as *mut libc::c_void;
            iovs[n].iov_len = batch.lens[k];
            n += 1;
        }
        for (hdr, iov) in hdrs.iter_mut().zip(iovs.iter_mut()).take(n) {
            hdr.msg_hdr.msg_iov = iov;
            hdr.msg_hdr.msg_iovlen = 1;
        }
        let mut sent = 0;
        let mut first_error = None;
        // Bit k: the k-th frame handed over was refused.
        let mut refused = 0u64;
        while sent < n {
            let rest = &mut hdrs[sent..n];
            // SAFETY: headers over frames of `batch`, each valid for its length; the socket is
            // bound, so no address.
            let r = unsafe {
                libc::sendmmsg(
                    self.fd.as_raw_fd(),
                    rest.as_mut_ptr(),
                    rest.len() as libc::c_uint,
                    0,
                )
            };
            match usize::try_from(r) {
                Ok(r) => sent += r,
                // The frame at `sent` is refused (longer than the link takes, no room left):
                // left out, and the rest sent.
                Err(_) => {
                    first_error.get_or_insert(io::Error::last_os_error());
                    refused |= 1 << sent;
                    sent += 1;
                }
            }
        }
        if let Some(c) = &self.capture {
            let frames = (0..batch.count)
                .filter(|&k| batch.lens[k] > 0)
                .enumerate()
                .filter(|(j, _)| refused & (1 << j) == 0)
                .map(|(_, k)| batch.frame(k));
            c.record_all(SystemTime::now(), Direction::Outbound, frames);
        }
        first_error.map_or(Ok(()), Err)
    }

    /// Sends one frame.
    pub fn send(&self, frame: &[u8]) -> io::Result<()> {
        // SAFETY: `frame` is valid for its length.
        let n = unsafe {
            libc::send(
                self.fd.as_raw_fd(),
                frame.as_ptr() as *const libc::c_void,
                frame.len(),
                0,
            )
        };
        if n < 0 {
            return Err(io::Error::last_os_error());
        }
        if let Some(c) = &self.capture {
            c.record(SystemTime::now(), Direction::Outbound, frame);
        }
        Ok(())
    }
}

impl Drop for RawSocket {
    fn drop(&mut self) {
        self.flush_capture();
    }
}

/// The socket's descriptor, for an event loop to wait on (e.g. `async_io::Async`).
impl AsFd for RawSocket {
    fn as_fd(&self) -> BorrowedFd<'_> {
        self.fd.as_fd()
    }
}

impl AsRawFd for RawSocket {
    fn as_raw_fd(&self) -> RawFd {
        self.fd.as_raw_fd()
    }
}

/// Frames received or to be sent together, each in a buffer of its own: what
/// [`RawSocket::recv_batch`] fills and [`RawSocket::send_batch`] sends. A frame is changed in
/// place ([`Batch::frame_mut`]), so that an answer goes back in the buffer its frame came in.
#[derive(Debug, Clone)]
pub struct Batch {
    bufs: Vec<Vec<u8>>,
    /// The length of each frame held; 0 for one not to be sent.
    lens: Vec<usize>,
    /// Frames held.
    count: usize,
}

impl Batch {
    /// The most frames a batch holds.
    pub const MAX: usize = 64;

    /// A batch of up to `frames` frames (1 to [`Batch::MAX`]) of up to `size` bytes each.
    pub fn new(frames: usize, size: usize) -> Batch {
        let frames = frames.clamp(1, Batch::MAX);
        Batch {
            bufs: vec![vec![0; size]; frames],
            lens: vec![0; frames],
            count: 0,
        }
    }

    /// Frames held.
    pub fn len(&self) -> usize {
        self.count
    }

    /// True when it holds none.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// True when it holds as many as it can.
    pub fn is_full(&self) -> bool {
        self.count == self.bufs.len()
    }

    /// Frame `k` (0 = first); empty once skipped.
    pub fn frame(&self, k: usize) -> &[u8] {
        &self.bufs[k][..self.lens[k]]
    }

    /// Frame `k`, to change in place.
    pub fn frame_mut(&mut self, k: usize) -> &mut [u8] {
        let len = self.lens[k];
        &mut self.bufs[k][..len]
    }

    /// Leaves frame `k` out of what [`RawSocket::send_batch`] sends.
    pub fn skip(&mut self, k: usize) {
        self.lens[k] = 0;
    }

    /// Holds no frame.
    pub fn clear(&mut self) {
        self.count = 0;
    }

    /// Adds a copy of `frame` (cut to the buffer's size) to send; false when full.
    pub fn push(&mut self, frame: &[u8]) -> bool {
        if self.is_full() {
            return false;
        }
        let buf = &mut self.bufs[self.count];
        let n = frame.len().min(buf.len());
        buf[..n].copy_from_slice(&frame[..n]);
        self.lens[self.count] = n;
        self.count += 1;
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A batch holds 1 to [`Batch::MAX`] frames, each a copy cut to its buffer's size, changed
    /// in place; a skipped frame is empty (nothing to send), and a cleared batch holds none.
    #[test]
    fn a_batch_holds_its_frames_in_order() {
        let mut b = Batch::new(0, 4);
        assert!(b.is_empty() && !b.is_full());
        assert!(b.push(&[1, 2, 3, 4, 5]));
        assert_eq!((b.len(), b.frame(0)), (1, &[1u8, 2, 3, 4][..]));
        assert!(b.is_full() && !b.is_empty());
        assert!(!b.push(&[9]), "one frame at least, and no more than asked");
        b.frame_mut(0)[0] = 7;
        assert_eq!(b.frame(0), [7, 2, 3, 4]);
        b.skip(0);
        assert_eq!((b.len(), b.frame(0)), (1, &[][..]));
        b.clear();
        assert!(b.is_empty());

        let mut b = Batch::new(Batch::MAX + 1, 2);
        for k in 0..Batch::MAX {
            assert!(b.push(&[k as u8]), "frame {k}");
        }
        assert!(!b.push(&[0]), "at most Batch::MAX");
        assert_eq!(b.len(), Batch::MAX);
        assert_eq!(
            (b.frame(0), b.frame(Batch::MAX - 1)),
            (&[0u8][..], &[63u8][..])
        );
    }
}
