//! An AF_PACKET raw socket bound to one interface for EtherType 0x88A4 (Linux): what the emulator
//! receives EtherCAT frames on and sends them back on.

use std::ffi::CString;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::time::Duration;

use crate::frame::ETHERTYPE;

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
        // SAFETY: socket(2) with constant arguments; the descriptor is owned at once.
        let fd = check(unsafe {
            libc::socket(
                libc::AF_PACKET,
                libc::SOCK_RAW | libc::SOCK_NONBLOCK | libc::SOCK_CLOEXEC,
                libc::c_int::from(proto),
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
        Ok(RawSocket {
            fd,
            iface: iface.into(),
        })
    }

    /// The interface.
    pub fn interface(&self) -> &str {
        &self.iface
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
            return Ok(Some((n as usize).min(buf.len())));
        }
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
        Ok(())
    }
}
