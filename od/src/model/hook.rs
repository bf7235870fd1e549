//! The one way a device model sits behind its dictionary, on CANopen and on EtherCAT alike.
//!
//! A model implements [`DeviceHook`]: it names the objects it owns, answers their current values and
//! takes the values written to them, each write with the instant it is made. A device that runs in
//! time implements [`Device`] too (the hook plus its clock, its SYNC, its reset and its errors): the
//! CANopen node and the EtherCAT unit drive every device through it, and run it up to the instant of
//! a write before they deliver the write. The dictionary keeps what it always holds (name, type, access,
//! limits, defaults) and checks every write before the model sees it; the model is the value of what
//! it owns, so nothing is copied through the dictionary on every cycle.
//!
//! - [`Bound`] is a dictionary with its model: the [`ObjectStore`] an SDO server (CANopen) or a CoE
//!   server (EtherCAT, [`crate::coe::server::CoeServer`]) serves, through [`Objects`];
//! - [`value`] is an entry's current value as a PDO or a process image carries it, and [`deliver`]
//!   what a received PDO or process image does to an entry;
//! - [`ProcessImage`] is the layout of a PDO or a SyncManager's process data, taken from the mapping
//!   objects of the description (0x1600+, 0x1A00+, 0x1C12/0x1C13), packed and unpacked through the
//!   model.
//!
//! ```
//! use std::time::Instant;
//!
//! use od::hook::{Bound, DeviceHook};
//! use od::sdo::store::ObjectStore;
//! use od::{AbortCode, AccessType, Address, DataType, Dictionary, Object, SubObject};
//!
//! /// A counter the device advances; the master reads it and may set it.
//! struct Counter(u16);
//!
//! impl DeviceHook for Counter {
//!     fn owns(&self, index: u16) -> bool {
//!         index == 0x2000
//!     }
//!     fn read(&self, _: Address, out: &mut [u8; 8]) -> Option<usize> {
//!         out[..2].copy_from_slice(&self.0.to_le_bytes());
//!         Some(2)
//!     }
//!     fn write(&mut self, _: Address, data: &[u8], _now: Instant) -> Result<(), AbortCode> {
//!         self.0 = u16::from_le_bytes([data[0], data[1]]);
//!         Ok(())
//!     }
//! }
//!
//! let mut dict = Dictionary::new();
//! dict.insert(Object::var(0x2000, SubObject::new("Counter", DataType::Unsigned16, AccessType::Rw)));
//! let mut counter = Counter(7);
//! let mut bound = Bound::new(&mut dict, &mut counter, Instant::now());
//! assert_eq!(bound.upload(Address::new(0x2000, 0)), Ok(vec![7, 0]));
//! bound.download(Address::new(0x2000, 0), &[0x34, 0x12]).unwrap();
//! assert_eq!(counter.0, 0x1234);
//! ```

use std::time::Instant;

use crate::abort::AbortCode;
use crate::dict::{Address, Dictionary};
use crate::emcy::DeviceError;
use crate::sdo::store::{DownloadCapacity, ObjectStore};

/// A device model that owns objects of its dictionary.
///
/// The dictionary has checked every write (existence, access, length, type, limits) before
/// [`check`](DeviceHook::check) and [`write`](DeviceHook::write) are called; the model adds its own
/// rules. An entry of an owned object whose [`read`](DeviceHook::read) answers `None` keeps the
/// dictionary's value (a parameter the model only needs to hear about).
pub trait DeviceHook {
    /// True for the objects the model owns: their reads and writes go through it.
    fn owns(&self, index: u16) -> bool;

    /// The current value of an entry of an owned object as little-endian bytes into `out` (process
    /// values of up to 64 bits): the number of bytes, or `None` when the dictionary's value stands.
    fn read(&self, at: Address, out: &mut [u8; 8]) -> Option<usize>;

    /// Whether the model would take `data` for `at`, asked for every entry of a write of several
    /// entries (a complete access) before any of them is written, so that a refusal changes nothing.
    /// By default every value the dictionary accepts.
    fn check(&self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        let _ = (at, data);
        Ok(())
    }

    /// Takes a value written at `now` to an entry of an owned object (by SDO, PDO or process data).
    /// A refusal leaves the model and the dictionary as they were. The caller has run a
    /// [`Device`] up to `now` before.
    fn write(&mut self, at: Address, data: &[u8], now: Instant) -> Result<(), AbortCode>;
}

/// A device that runs in time behind its dictionary: the [`DeviceHook`] with its clock, its
/// synchronisation, its reset and its errors. The one lifecycle of every device model (a CiA 402
/// drive application, the X67 bus controller, the SMD indexer), driven alike by the CANopen node and
/// the EtherCAT unit:
///
/// - [`handle_timeout`](Device::handle_timeout) whenever [`poll_timeout`](Device::poll_timeout)
///   has passed, and before any write at a later instant ([`DeviceHook::write`] carries it);
/// - [`sync`](Device::sync) at a SYNC (CANopen) or a SYNC0 / new output image (EtherCAT);
/// - [`reset`](Device::reset) at power-on values again (NMT reset node; EtherCAT Init);
/// - [`errors`](Device::errors) for what the node reports (EMCY, 0x1001, 0x1003).
///
/// No clock, socket or file inside: every input carries its instant.
pub trait Device: DeviceHook {
    /// Runs the device up to `now`.
    fn handle_timeout(&mut self, now: Instant);
    /// When [`handle_timeout`](Device::handle_timeout) is next due (`None`: nothing to do until
    /// an input arrives).
    fn poll_timeout(&self) -> Option<Instant>;
    /// The errors active now, each with its EMCY code. By default none.
    fn errors(&self, out: &mut Vec<DeviceError>) {
        let _ = out;
    }
    /// Back to power-on (NMT reset node), with time starting at `now`.
    fn reset(&mut self, now: Instant);
    /// A synchronisation at `now` (the device has run up to `now`, and the process data received
    /// before it is in its entries): the instant a cyclic synchronous drive takes its targets
    /// (CiA 301 §7.2.2.2, ETG.1020 SYNC0). By default nothing.
    fn sync(&mut self, now: Instant) {
        let _ = now;
    }
}

/// Runs `device` up to `at` before a write made at `at` reaches it: the timeout it asked for before
/// `at`, if any. What falls due at `at` itself runs after the write, with the host's own timers.
/// True when it ran. What the CANopen node and the EtherCAT unit both do before they deliver a
/// write.
pub fn run_before<D: Device + ?Sized>(device: &mut D, at: Instant) -> bool {
    let due = device.poll_timeout().is_some_and(|t| t < at);
    if due {
        device.handle_timeout(at);
    }
    due
}

/// The model of a device that has none: it owns nothing, the dictionary is the device.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoHook;

impl DeviceHook for NoHook {
    fn owns(&self, _: u16) -> bool {
        false
    }

    fn read(&self, _: Address, _: &mut [u8; 8]) -> Option<usize> {
        None
    }

    fn write(&mut self, _: Address, _: &[u8], _: Instant) -> Result<(), AbortCode> {
        Ok(())
    }
}

impl Device for NoHook {
    fn handle_timeout(&mut self, _: Instant) {}

    fn poll_timeout(&self) -> Option<Instant> {
        None
    }

    fn reset(&mut self, _: Instant) {}
}

/// What a server serves: a dictionary and the model behind it.
pub trait Objects {
    /// The dictionary and the model, borrowed together.
    fn split(&mut self) -> (&mut Dictionary, &mut dyn DeviceHook);
}

impl Objects for Dictionary {
    fn split(&mut self) -> (&mut Dictionary, &mut dyn DeviceHook) {
        // A zero-sized value: leaking it allocates nothing.
        (self, Box::leak(Box::new(NoHook)))
    }
}

/// A dictionary with its model, borrowed for one request made at `now`.
pub struct Bound<'a> {
    /// The dictionary.
    pub dict: &'a mut Dictionary,
    /// The model.
    pub hook: &'a mut dyn DeviceHook,
    /// When the request is made: the instant its writes carry.
    pub now: Instant,
}

impl<'a> Bound<'a> {
    /// `dict` with `hook` behind it, for a request made at `now`.
    pub fn new(dict: &'a mut Dictionary, hook: &'a mut dyn DeviceHook, now: Instant) -> Bound<'a> {
        Bound { dict, hook, now }
    }
}

impl Objects for Bound<'_> {
    fn split(&mut self) -> (&mut Dictionary, &mut dyn DeviceHook) {
        (self.dict, self.hook)
    }
}

/// The current value of `at` (the model's for what it owns, else the dictionary's), with no access
/// check: what a TPDO or an input process image carries. Empty when the entry does not exist.
pub fn value<'a>(
    dict: &'a Dictionary,
    hook: &dyn DeviceHook,
    at: Address,
    buf: &'a mut [u8; 8],
) -> &'a [u8] {
    if hook.owns(at.index) {
        if let Some(n) = hook.read(at, buf) {
            return &buf[..n.min(8)];
        }
    }
    dict.entry(at.index, at.sub).map_or(&[][..], |e| &e.value)
}

/// What a received RPDO or output process image does to `at` at `now`: the model takes the value of
/// what it owns (a refusal drops it), the dictionary stores it. No access check (process data is
/// written whatever the entry's SDO access); a value the dictionary cannot hold is dropped.
pub fn deliver(
    dict: &mut Dictionary,
    hook: &mut dyn DeviceHook,
    at: Address,
    data: &[u8],
    now: Instant,
) {
    if hook.owns(at.index) && hook.write(at, data, now).is_err() {
        return;
    }
    let _ = dict.store(at.index, at.sub, data);
}

/// An SDO upload of `at`: refused as the dictionary refuses it (no entry, write-only), else the
/// current [`value`].
pub fn upload(dict: &Dictionary, hook: &dyn DeviceHook, at: Address) -> Result<Vec<u8>, AbortCode> {
    dict.read(at.index, at.sub).map_err(|e| e.abort_code())?;
    let mut buf = [0u8; 8];
    Ok(value(dict, hook, at, &mut buf).to_vec())
}

/// The dictionary's checks of a download of `data` to `at` (existence, access, length, type,
/// limits), then the model's for what it owns ([`DeviceHook::check`]).
pub fn check_download(
    dict: &Dictionary,
    hook: &dyn DeviceHook,
    at: Address,
    data: &[u8],
) -> Result<(), AbortCode> {
    let entry = dict.entry(at.index, at.sub).map_err(|e| e.abort_code())?;
    if !entry.access.kind.writable() {
        return Err(AbortCode::ReadOnly);
    }
    dict.check(at.index, at.sub, data)
        .map_err(|e| e.abort_code())?;
    if hook.owns(at.index) {
        hook.check(at, data)?;
    }
    Ok(())
}

/// Stores a download [`check_download`] accepted, made at `now`: the model takes it first (a
/// refusal changes nothing), then the dictionary.
pub fn store_download(
    dict: &mut Dictionary,
    hook: &mut dyn DeviceHook,
    at: Address,
    data: &[u8],
    now: Instant,
) -> Result<(), AbortCode> {
    if hook.owns(at.index) {
        hook.write(at, data, now)?;
    }
    dict.store(at.index, at.sub, data)
        .map_err(|e| e.abort_code())
}

impl ObjectStore for Bound<'_> {
    fn upload(&mut self, at: Address) -> Result<Vec<u8>, AbortCode> {
        upload(self.dict, self.hook, at)
    }

    fn download_capacity(&self, at: Address) -> Result<DownloadCapacity, AbortCode> {
        self.dict.download_capacity(at)
    }

    fn download(&mut self, at: Address, data: &[u8]) -> Result<(), AbortCode> {
        check_download(self.dict, self.hook, at, data)?;
        store_download(self.dict, self.hook, at, data, self.now)
    }
}

/// One entry of a process image: where it is, at which bit and how many bits it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ImageEntry {
    /// The mapped entry; index 0 (or a CiA 301 dummy type, 0x0001–0x0007) is padding.
    pub at: Address,
    /// The first bit in the image.
    pub bit: u32,
    /// Its length in bits.
    pub bits: u32,
}

impl ImageEntry {
    /// True for padding (a gap or a dummy entry): nothing is read or written.
    pub fn is_padding(&self) -> bool {
        self.at.index <= 0x0007
    }
}

/// Why a process image could not be made from the mapping objects.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ImageError {
    /// A mapping or assignment object is not in the dictionary, or has no value at the sub-index.
    #[error(
        "0x{index:04X}:{sub:02X}, a PDO mapping or assignment entry, is not in the dictionary"
    )]
    Missing {
        /// Index.
        index: u16,
        /// Sub-index.
        sub: u8,
    },
}

/// The layout of a PDO or of a SyncManager's process data: the mapped entries in order, packed
/// without gaps (bit by bit, little-endian), as CiA 301 §7.4.8 and ETG.1000.6 §5.6.7.4 lay them out.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ProcessImage {
    entries: Vec<ImageEntry>,
    bits: u32,
}

impl ProcessImage {
    /// The image of one PDO mapping object (`0x1600`+, `0x1A00`+): its entries `1..=sub 0`, each
    /// UNSIGNED32 `index << 16 | sub << 8 | bits`.
    pub fn from_mapping(dict: &Dictionary, mapping: u16) -> Result<ProcessImage, ImageError> {
        let mut image = ProcessImage::default();
        image.push_mapping(dict, mapping)?;
        Ok(image)
    }

    /// The image of a SyncManager from its PDO assignment object (`0x1C12` outputs, `0x1C13` inputs,
    /// ETG.1000.6 §5.6.7.4): the assigned mapping objects one after the other. An entry 0 among the
    /// counted ones assigns nothing (SOES counts all its entries and leaves the unused ones 0; masters
    /// skip them, as SOEM's `ecx_readPDOassign` does).
    pub fn from_assignment(dict: &Dictionary, assignment: u16) -> Result<ProcessImage, ImageError> {
        let mut image = ProcessImage::default();
        for sub in 1..=u8_at(dict, assignment, 0)? {
            let mapping = uint_at(dict, assignment, sub)? as u16;
            if mapping != 0 {
                image.push_mapping(dict, mapping)?;
            }
        }
        Ok(image)
    }

    fn push_mapping(&mut self, dict: &Dictionary, mapping: u16) -> Result<(), ImageError> {
        for sub in 1..=u8_at(dict, mapping, 0)? {
            let word = uint_at(dict, mapping, sub)? as u32;
            let bits = word & 0xFF;
            self.entries.push(ImageEntry {
                at: Address::new((word >> 16) as u16, (word >> 8) as u8),
                bit: self.bits,
                bits,
            });
            self.bits += bits;
        }
        Ok(())
    }

    /// The entries in order.
    pub fn entries(&self) -> &[ImageEntry] {
        &self.entries
    }

    /// The image's length in bits.
    pub fn bits(&self) -> u32 {
        self.bits
    }

    /// The image's length in bytes.
    pub fn len(&self) -> usize {
        self.bits.div_ceil(8) as usize
    }

    /// True for an image with no bits.
    pub fn is_empty(&self) -> bool {
        self.bits == 0
    }

    /// Packs the current [`value`]s of the mapped entries into `out` (padding and bits past the
    /// values are 0; an image longer than `out` is cut at its end).
    pub fn pack(&self, dict: &Dictionary, hook: &dyn DeviceHook, out: &mut [u8]) {
        out.fill(0);
        let mut buf = [0u8; 8];
        for e in self.entries.iter().filter(|e| !e.is_padding()) {
            put_bits(out, e.bit, e.bits, value(dict, hook, e.at, &mut buf));
        }
    }

    /// Unpacks `data`, received at `now`, into the mapped entries ([`deliver`]): each entry whose
    /// bits `data` holds whole, in order; the entries past a short `data` are left as they are.
    pub fn unpack(
        &self,
        data: &[u8],
        dict: &mut Dictionary,
        hook: &mut dyn DeviceHook,
        now: Instant,
    ) {
        let have = data.len() as u64 * 8;
        for e in self.entries.iter().filter(|e| !e.is_padding()) {
            if u64::from(e.bit) + u64::from(e.bits) > have {
                break;
            }
            let bytes = get_bits(data, e.bit, e.bits);
            deliver(dict, hook, e.at, &bytes, now);
        }
    }
}

fn uint_at(dict: &Dictionary, index: u16, sub: u8) -> Result<u64, ImageError> {
    dict.read_value(index, sub)
        .ok()
        .and_then(|v| v.as_i128())
        .and_then(|v| u64::try_from(v).ok())
        .ok_or(ImageError::Missing { index, sub })
}

fn u8_at(dict: &Dictionary, index: u16, sub: u8) -> Result<u8, ImageError> {
    uint_at(dict, index, sub).map(|v| v.min(255) as u8)
}

/// Copies the low `bits` bits of `value` (little-endian) into `out` at bit offset `at`; bits past
/// `out` are dropped.
pub fn put_bits(out: &mut [u8], at: u32, bits: u32, value: &[u8]) {
    for i in 0..bits {
        let v = value
            .get((i / 8) as usize)
            .map_or(0, |b| (b >> (i % 8)) & 1);
        let pos = at + i;
        if let Some(byte) = out.get_mut((pos / 8) as usize) {
            *byte = (*byte & !(1 << (pos % 8))) | (v << (pos % 8));
        }
    }
}

/// The `bits` bits of `data` from bit offset `at`, little-endian, in whole bytes (bits past `data`
/// are 0).
pub fn get_bits(data: &[u8], at: u32, bits: u32) -> Vec<u8> {
    let mut out = vec![0u8; bits.div_ceil(8) as usize];
    for i in 0..bits {
        let pos = at + i;
        let v = data
            .get((pos / 8) as usize)
            .map_or(0, |b| (b >> (pos % 8)) & 1);
        out[(i / 8) as usize] |= v << (i % 8);
    }
    out
}
