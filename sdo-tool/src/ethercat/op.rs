//! The chain in Op, for a command that moves a drive: the process data exchanged every [`CYCLE`]
//! while the command runs (in an SDO transfer and while it waits), each entry a slave maps in its
//! RxPDOs written through the process data (an SDO write there would be overwritten at the next
//! cycle), everything else by CoE as in Pre-Op. The chain goes back to Init when the session ends,
//! as a Pre-Op session's does.

use std::cell::Cell;
use std::time::{Duration, Instant};

use ethercrab::subdevice_group::Op;
use ethercrab::{DefaultLock, MainDevice, SubDeviceGroup};
use od::dict::Address;

use super::{download, drive, upload, EthercatError, EthercatSession, Link, MAX_PDI, MAX_SLAVES};
use crate::{SdoAccess, ToolError};

/// The process data cycle.
pub const CYCLE: Duration = Duration::from_millis(2);

type OpGroup = SubDeviceGroup<MAX_SLAVES, MAX_PDI, DefaultLock, Op>;

/// An entry of a slave's RxPDOs and where its bytes are in the slave's outputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Mapped {
    index: u16,
    sub: u8,
    /// Byte offset in the slave's outputs.
    offset: usize,
    /// Bytes.
    len: usize,
}

/// An EtherCAT chain in Op.
pub struct OpSession {
    link: Link,
    group: Box<OpGroup>,
    /// Each slave's RxPDO entries, by position − 1.
    maps: Vec<Vec<Mapped>>,
}

impl EthercatSession {
    /// The chain to Op: each slave's RxPDO entries read (0x1C12 and the PDOs it assigns) and its
    /// outputs set to what those entries hold now (a target position 0x607A to the position actual
    /// 0x6064, so that no drive jumps), then Safe-Op and Op with the process data exchanged from the
    /// first Safe-Op cycle on; at most the session's timeout for Op.
    pub fn into_op(mut self) -> Result<OpSession, ToolError> {
        let mut maps = Vec::new();
        let mut initial = Vec::new();
        for position in 1..=self.group.len() {
            let node = position as u8;
            let map = self.rx_map(node);
            let mut values = Vec::new();
            for m in &map {
                let source = match m.index & 0x07FF {
                    0x007A => Address::new(m.index - 0x7A + 0x64, m.sub),
                    _ => Address::new(m.index, m.sub),
                };
                let v = self.read_bytes(node, source).unwrap_or_default();
                values.push(v);
            }
            maps.push(map);
            initial.push(values);
        }
        let EthercatSession { mut link, group } = self;
        let md = &link.maindevice;
        let safe = drive(&mut link.tx_rx, group.into_safe_op(md))
            .map_err(|e| link.ended(e))?
            .map_err(|e| transition(&link, "Safe-Op", e))?;
        for (i, map) in maps.iter().enumerate() {
            let sd = safe
                .subdevice(md, i)
                .map_err(|e| transition(&link, "Safe-Op", e))?;
            let mut out = sd.outputs_raw_mut();
            for (m, v) in map.iter().zip(&initial[i]) {
                if let Some(dst) = out.get_mut(m.offset..m.offset + m.len) {
                    let n = v.len().min(m.len);
                    dst[..n].copy_from_slice(&v[..n]);
                }
            }
        }
        let op = drive(&mut link.tx_rx, safe.request_into_op(md))
            .map_err(|e| link.ended(e))?
            .map_err(|e| transition(&link, "Op", e))?;
        let deadline = Instant::now() + link.timeout.max(Duration::from_secs(1));
        loop {
            let r = drive(&mut link.tx_rx, op.tx_rx(md)).map_err(|e| link.ended(e))?;
            if r.as_ref().is_ok_and(|r| r.all_op()) {
                break;
            }
            if Instant::now() >= deadline {
                let why = match r {
                    Ok(r) => format!("states {:?}", r.group_state()),
                    Err(e) => e.to_string(),
                };
                return Err(EthercatError::Op {
                    interface: link.interface.clone(),
                    detail: why,
                }
                .into());
            }
            std::thread::sleep(CYCLE);
        }
        Ok(OpSession {
            link,
            group: Box::new(op),
            maps,
        })
    }

    /// The entries of the RxPDOs 0x1C12 assigns to the slave at `node` (none where it has no
    /// 0x1C12 or answers none of it), with their places in its outputs; entries that do not start
    /// and end on a byte are left out (they are written by CoE).
    fn rx_map(&mut self, node: u8) -> Vec<Mapped> {
        let mut read = |index: u16, sub: u8| -> Option<u32> {
            let b = self.read_bytes(node, Address::new(index, sub)).ok()?;
            let mut v = [0u8; 4];
            let n = b.len().min(4);
            v[..n].copy_from_slice(&b[..n]);
            Some(u32::from_le_bytes(v))
        };
        let mut map = Vec::new();
        let mut bit = 0usize;
        let pdos = read(0x1C12, 0).unwrap_or(0).min(255) as u8;
        for k in 1..=pdos {
            let Some(pdo) = read(0x1C12, k) else { break };
            let entries = read(pdo as u16, 0).unwrap_or(0).min(255) as u8;
            for j in 1..=entries {
                let Some(e) = read(pdo as u16, j) else { break };
                let (index, sub, bits) = ((e >> 16) as u16, (e >> 8) as u8, (e & 0xFF) as usize);
                if index != 0 && bit & 7 == 0 && bits & 7 == 0 && bits > 0 {
                    map.push(Mapped {
                        index,
                        sub,
                        offset: bit / 8,
                        len: bits / 8,
                    });
                }
                bit += bits;
            }
        }
        map
    }
}

/// A transition the chain did not make.
fn transition(link: &Link, state: &str, e: ethercrab::error::Error) -> ToolError {
    EthercatError::Op {
        interface: link.interface.clone(),
        detail: format!("to {state}: {e}"),
    }
    .into()
}

/// `f` with the process data exchanged every [`CYCLE`] meanwhile. The exchange in flight when `f`
/// ends is waited for rather than dropped: a frame given up on would come back to a master that no
/// longer expects it.
async fn with_cycles<T>(
    group: &OpGroup,
    md: &MainDevice<'_>,
    f: impl std::future::Future<Output = T>,
) -> T {
    let done = Cell::new(false);
    let work = async {
        let r = f.await;
        done.set(true);
        r
    };
    let cycles = async {
        while !done.get() {
            let _ = group.tx_rx(md).await;
            if done.get() {
                break;
            }
            async_io::Timer::after(CYCLE).await;
        }
    };
    futures_lite::future::zip(work, cycles).await.0
}

impl OpSession {
    /// Runs `f` with the process data cycling.
    fn cycling<T>(&mut self, f: impl std::future::Future<Output = T>) -> Result<T, ToolError> {
        let (group, md) = (&self.group, &self.link.maindevice);
        drive(&mut self.link.tx_rx, with_cycles(group, md, f)).map_err(|e| self.link.ended(e))
    }
}

impl SdoAccess for OpSession {
    fn check_node(&self, node: u8) -> Result<(), ToolError> {
        self.link.check_position(node, self.group.len())
    }

    fn read_bytes(&mut self, node: u8, addr: Address) -> Result<Vec<u8>, ToolError> {
        self.check_node(node)?;
        let (group, md) = (&self.group, &self.link.maindevice);
        let sd = group.subdevice(md, usize::from(node) - 1);
        let both = with_cycles(group, md, upload(sd, addr));
        let r = drive(&mut self.link.tx_rx, both).map_err(|e| self.link.ended(e))?;
        self.link.uploaded(node, addr, r)
    }

    fn write_bytes(&mut self, node: u8, addr: Address, data: &[u8]) -> Result<(), ToolError> {
        self.check_node(node)?;
        let mapped = self.maps[usize::from(node) - 1]
            .iter()
            .find(|m| m.index == addr.index && m.sub == addr.sub && m.len == data.len())
            .copied();
        if let Some(m) = mapped {
            {
                let sd = self
                    .group
                    .subdevice(&self.link.maindevice, usize::from(node) - 1)
                    .map_err(|e| self.link.error(node, addr, e.into()))?;
                let mut out = sd.outputs_raw_mut();
                if let Some(dst) = out.get_mut(m.offset..m.offset + m.len) {
                    dst.copy_from_slice(data);
                }
            }
            // Sent at the next cycle; two, so that the slave has taken it before what follows.
            return self.idle(CYCLE * 2);
        }
        let (group, md, timeout) = (&self.group, &self.link.maindevice, self.link.timeout);
        let sd = group.subdevice(md, usize::from(node) - 1);
        let both = with_cycles(group, md, download(md, sd, addr, data, timeout));
        let r = drive(&mut self.link.tx_rx, both).map_err(|e| self.link.ended(e))?;
        r.map_err(|f| self.link.error(node, addr, f))
    }

    fn idle(&mut self, d: Duration) -> Result<(), ToolError> {
        self.cycling(async_io::Timer::after(d)).map(|_| ())
    }
}
