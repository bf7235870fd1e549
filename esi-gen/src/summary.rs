//! `esi-gen check`: loads descriptions, ranks what the readers and `od::validate` found (errors first,
//! then warnings, each at `file:line:column`), and prints a one-screen summary of one file or one line
//! per file for a folder of vendor files, as text or JSON.
//!
//! An error is what makes a file unusable as written (see `od::report`); `--strict` counts warnings as
//! errors. With `--round-trip` each file is also written in its own format and read back, and must come
//! back equal; a CANopen description must also convert to an EDS that reads back without errors.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

use od::device::DeviceDescription;
use od::load::Format;
use od::report::{Finding, Reading, Severity};
use od::validate::validate_mapped;
use od::Position;
use serde::Serialize;

/// How to check.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Only the devices this selection names (type name, name or product code).
    pub device: Option<String>,
    /// Warnings count as errors.
    pub strict: bool,
    /// Write each file in its own format (and CANopen ones as EDS) and read it back.
    pub round_trip: bool,
}

/// One finding with the device it is about, in a file that describes several.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Located {
    /// The finding.
    pub finding: Finding,
    /// The device's name and revision, when the file describes more than one.
    pub device: Option<String>,
}

/// A device in a report.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct DeviceLine {
    /// Type name, else product name.
    pub name: String,
    /// Product name.
    pub product_name: String,
    /// Vendor ID.
    pub vendor_id: u32,
    /// Product code.
    pub product_code: u32,
    /// Revision number.
    pub revision: u32,
    /// Objects in the dictionary.
    pub objects: usize,
    /// Entries (sub-objects) in the dictionary.
    pub entries: usize,
    /// The entries the description gives `ObjFlags` (CiA 306 §4.6.3, XDD `objFlags`), in address
    /// order.
    pub flagged: Vec<Flagged>,
}

/// An entry with `ObjFlags`: what a configuration tool leaves out for it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct Flagged {
    /// Object index.
    pub index: u16,
    /// Sub-index.
    pub sub: u8,
    /// The entry's name.
    pub name: String,
    /// The flags, the object's and the entry's own together ([`od::object::Object::flags_of`]).
    pub flags: u32,
    /// What they ask: `sdo-tool apply` does not write an entry flagged "refuse write on download"
    /// (bit 0), `sdo-tool dump` does not read one flagged "refuse read on scan" (bit 1).
    pub meaning: String,
}

/// The entries of `dev` with `ObjFlags`.
fn flagged(dev: &DeviceDescription) -> Vec<Flagged> {
    dev.dictionary
        .objects()
        .flat_map(|o| {
            o.subs.iter().filter_map(move |(&sub, s)| {
                let flags = o.flags_of(sub);
                (!flags.is_empty()).then(|| Flagged {
                    index: o.index,
                    sub,
                    name: s.name.clone(),
                    flags: flags.bits(),
                    meaning: flag_meaning(flags),
                })
            })
        })
        .collect()
}

/// What a tool makes of `flags`, in words.
fn flag_meaning(flags: od::object::ObjFlags) -> String {
    use od::object::ObjFlags;
    let mut words = Vec::new();
    if flags.contains(ObjFlags::REFUSE_WRITE_ON_DOWNLOAD) {
        words.push("refuse write on download: sdo-tool apply does not write it");
    }
    if flags.contains(ObjFlags::REFUSE_READ_ON_SCAN) {
        words.push("refuse read on scan: sdo-tool dump does not read it");
    }
    if flags.bits() & !0b11 != 0 {
        words.push("reserved bits set: no tool acts on them");
    }
    words.join("; ")
}

/// What checking one file found.
#[derive(Debug, Clone)]
pub struct FileReport {
    /// The file.
    pub path: PathBuf,
    /// Its format, when it could be told.
    pub format: Option<Format>,
    /// The devices checked.
    pub devices: Vec<DeviceLine>,
    /// Every finding, errors first, then in file order.
    pub findings: Vec<Located>,
    /// Time to read and check, in milliseconds (round trip not included).
    pub milliseconds: f64,
    /// Differences of the round trip, one line each (`--round-trip`); empty when it came back equal.
    pub round_trip: Option<Vec<String>>,
    /// The file could not be read at all (I/O, not a file, unknown format, not well-formed).
    pub unreadable: bool,
}

impl FileReport {
    /// Findings of severity error.
    pub fn errors(&self) -> usize {
        self.count(Severity::Error)
    }

    /// Findings of severity warning.
    pub fn warnings(&self) -> usize {
        self.count(Severity::Warning)
    }

    fn count(&self, severity: Severity) -> usize {
        self.findings
            .iter()
            .filter(|f| f.finding.severity == severity)
            .count()
    }

    /// True when the file has no error and, when one was made, its round trip came back equal.
    pub fn passed(&self) -> bool {
        self.errors() == 0 && self.round_trip.as_ref().is_none_or(|d| d.is_empty())
    }

    /// `path:line:column: severity: device: address: message` (the parts that are known).
    pub fn finding_line(&self, f: &Located) -> String {
        let mut line = self.path.display().to_string();
        if let Some(p) = f.finding.position {
            let _ = write!(line, ":{p}");
        }
        let _ = write!(line, ": {}", f.finding.severity);
        if let Some(d) = &f.device {
            let _ = write!(line, ": {d}");
        }
        if let Some(a) = f.finding.address {
            let _ = write!(line, ": {a}");
        }
        let _ = write!(line, ": {}", f.finding.message);
        line
    }
}

/// The label of a device among several: type name and revision.
pub fn label(dev: &DeviceDescription) -> String {
    format!(
        "{} rev 0x{:08X}",
        crate::device_name(dev),
        dev.identity.revision
    )
}

fn device_line(dev: &DeviceDescription) -> DeviceLine {
    let d = &dev.dictionary;
    DeviceLine {
        name: crate::device_name(dev).to_string(),
        product_name: dev.identity.product_name.clone(),
        vendor_id: dev.identity.vendor_id,
        product_code: dev.identity.product_code,
        revision: dev.identity.revision,
        objects: d.len(),
        entries: d.objects().map(|o| o.subs.len()).sum(),
        flagged: flagged(dev),
    }
}

fn error_at(position: Option<Position>, message: String) -> Located {
    Located {
        finding: Finding {
            severity: Severity::Error,
            position,
            address: None,
            message,
        },
        device: None,
    }
}

/// Checks one file.
pub fn check_file(path: &Path, options: &Options) -> FileReport {
    check_file_keeping(path, options).0
}

/// Checks one file as [`check_file`] does, and answers the devices checked too.
pub fn check_file_keeping(path: &Path, options: &Options) -> (FileReport, Vec<DeviceDescription>) {
    let started = Instant::now();
    let mut report = FileReport {
        path: path.to_path_buf(),
        format: None,
        devices: Vec::new(),
        findings: Vec::new(),
        milliseconds: 0.0,
        round_trip: None,
        unreadable: false,
    };
    let loaded = od::load::load_reading(path);
    let (format, reading) = match loaded {
        Ok(x) => x,
        Err(e) => {
            report.unreadable = true;
            report.format = od::load::read_limited(path, od::load::MAX_FILE_BYTES)
                .ok()
                .and_then(|bytes| Format::detect(path, &bytes));
            report.findings.push(match e {
                od::LoadError::Parse(p) => error_at(Some(p.position), p.message),
                other => error_at(None, strip_path(&other.to_string(), path)),
            });
            report.milliseconds = started.elapsed().as_secs_f64() * 1e3;
            return (report, Vec::new());
        }
    };
    report.format = Some(format);
    let Reading {
        devices,
        sources,
        findings,
    } = reading;
    let chosen: Vec<usize> = match options.device.as_deref() {
        None => (0..devices.len()).collect(),
        Some(wanted) => match crate::select::select_index(path, &devices, wanted) {
            Ok(i) => vec![i],
            Err(e) => {
                report
                    .findings
                    .push(error_at(None, strip_path(&e.to_string(), path)));
                Vec::new()
            }
        },
    };
    report
        .findings
        .extend(findings.into_iter().map(|finding| Located {
            finding,
            device: None,
        }));
    let several = chosen.len() > 1;
    for &i in &chosen {
        let dev = &devices[i];
        report.devices.push(device_line(dev));
        let map = sources.get(i).cloned().unwrap_or_default();
        let device = several.then(|| label(dev));
        report.findings.extend(
            validate_mapped(dev, &map)
                .into_iter()
                .map(|finding| Located {
                    finding,
                    device: device.clone(),
                }),
        );
    }
    if devices.is_empty() {
        report.findings.push(Located {
            finding: Finding {
                severity: Severity::Warning,
                position: None,
                address: None,
                message: "the file describes no device".into(),
            },
            device: None,
        });
    }
    if options.strict {
        for f in &mut report.findings {
            f.finding.severity = Severity::Error;
        }
    }
    sort_located(&mut report.findings);
    report.milliseconds = started.elapsed().as_secs_f64() * 1e3;
    let mut devices: Vec<Option<DeviceDescription>> = devices.into_iter().map(Some).collect();
    let picked: Vec<DeviceDescription> = chosen
        .iter()
        .filter_map(|&i| devices.get_mut(i).and_then(Option::take))
        .collect();
    if options.round_trip {
        report.round_trip = Some(round_trip(format, &picked));
    }
    (report, picked)
}

/// Errors first, then by place in the file, then by device and entry.
fn sort_located(list: &mut [Located]) {
    list.sort_by(|a, b| {
        b.finding
            .severity
            .cmp(&a.finding.severity)
            .then_with(|| {
                let key = |p: Option<Position>| p.map(|p| (p.line, p.column));
                key(a.finding.position).cmp(&key(b.finding.position))
            })
            .then_with(|| a.device.cmp(&b.device))
            .then_with(|| a.finding.address.cmp(&b.finding.address))
    });
}

/// A load error's text without the path in front (the report line puts it there).
fn strip_path(text: &str, path: &Path) -> String {
    let shown = path.display().to_string();
    text.strip_prefix(&shown)
        .and_then(|t| t.strip_prefix(": "))
        .unwrap_or(text)
        .to_string()
}

/// What differs between `devices` and the devices read back from what was written of them, as lines:
/// the devices paired by product code and revision, each pair compared whole ([`od::diff::diff_devices`]),
/// prefixed with the device's label where there are several.
pub fn differences(devices: &[DeviceDescription], back: &[DeviceDescription]) -> Vec<String> {
    let several = devices.len() > 1;
    let mut out = Vec::new();
    for pairing in od::diff::pair_devices(devices, back) {
        match pairing {
            od::diff::Pairing::Both(i, j) => {
                for d in od::diff::diff_devices(&devices[i], &back[j]) {
                    out.push(if several {
                        format!("{}: {d}", label(&devices[i]))
                    } else {
                        d.to_string()
                    });
                }
            }
            od::diff::Pairing::OnlyInA(i) => {
                out.push(format!("{}: not read back", label(&devices[i])));
            }
            od::diff::Pairing::OnlyInB(j) => {
                out.push(format!("{}: read back, but not written", label(&back[j])));
            }
        }
    }
    out
}

/// Writes `devices` in `format`, reads them back and lists what differs; a CANopen description is
/// also written as an EDS, which must read back without errors.
pub fn round_trip(format: Format, devices: &[DeviceDescription]) -> Vec<String> {
    let mut out = Vec::new();
    let written = match format {
        Format::Esi => od::esi::write_all(devices),
        Format::Xdd => devices.first().map(od::xdd::write).unwrap_or_default(),
        Format::Eds => devices.first().map(od::eds::write_eds).unwrap_or_default(),
        Format::Dcf => devices.first().map(od::eds::write_dcf).unwrap_or_default(),
    };
    if devices.is_empty() {
        return out;
    }
    let name = format!("written {format}");
    match od::load::read_bytes(written.as_bytes(), &name, format) {
        Err(e) => out.push(format!("written as {format}, it does not read back: {e}")),
        Ok(back) => out.extend(differences(devices, &back)),
    }
    if format != Format::Esi {
        let eds = od::eds::write_eds(&devices[0]);
        match od::eds::read_file(eds.as_bytes(), "written EDS") {
            Err(e) => out.push(format!("written as EDS, it does not read back: {e}")),
            Ok(r) => {
                let map = r.sources.first().cloned().unwrap_or_default();
                for dev in &r.devices {
                    for f in validate_mapped(dev, &map) {
                        if f.severity == Severity::Error {
                            out.push(format!("written as EDS: {f}"));
                        }
                    }
                }
            }
        }
    }
    out
}

/// Runs `esi-gen check`: one file gets the one-screen summary, several files or a folder a line per
/// file and a summary. Exit code 1 when any file has an error (or, with `--round-trip`, does not come
/// back equal), else 0.
pub fn run(args: &crate::CheckArgs, out: &mut dyn std::io::Write) -> crate::Outcome {
    let options = Options {
        device: args.device.clone(),
        strict: args.strict,
        round_trip: args.round_trip,
    };
    let started = Instant::now();
    let single = args.inputs.len() == 1 && !args.inputs[0].is_dir();
    if single {
        let path = &args.inputs[0];
        if let Err(source) = std::fs::metadata(path) {
            return Err(crate::Error::Io {
                path: path.clone(),
                source,
            });
        }
        let (report, devices) = check_file_keeping(path, &options);
        let text = if args.json {
            json(
                std::slice::from_ref(&report),
                started.elapsed().as_secs_f64() * 1e3,
            )
        } else {
            text_one(&report, &devices, args.all)
        };
        crate::write_out(out, &text)?;
        return Ok(u8::from(!report.passed()));
    }
    let mut paths = Vec::new();
    for input in &args.inputs {
        if input.is_dir() {
            paths.extend(files_in(input).map_err(|source| crate::Error::Io {
                path: input.clone(),
                source,
            })?);
        } else {
            paths.push(input.clone());
        }
    }
    let mut reports = Vec::with_capacity(paths.len());
    for path in &paths {
        reports.push(check_file(path, &options));
    }
    let total = started.elapsed().as_secs_f64() * 1e3;
    let text = if args.json {
        json(&reports, total)
    } else {
        text_batch(&reports, args.all, total)
    };
    crate::write_out(out, &text)?;
    Ok(u8::from(!reports.iter().all(FileReport::passed)))
}

/// Text of a one-file check: the summary of each device and the findings (at most 20 unless `all`).
pub fn text_one(report: &FileReport, full: &[DeviceDescription], all: bool) -> String {
    let mut text = String::new();
    let format = report
        .format
        .map_or("unknown format".to_string(), |f| f.to_string());
    let _ = writeln!(
        text,
        "{}: {format}, {} device(s), read and checked in {:.1} ms",
        report.path.display(),
        report.devices.len(),
        report.milliseconds
    );
    if full.len() > 4 {
        for d in &report.devices {
            let _ = writeln!(
                text,
                "  {:<24} product code 0x{:08X}  revision 0x{:08X}  {} objects",
                d.name, d.product_code, d.revision, d.objects
            );
        }
    } else {
        for dev in full {
            summary(&mut text, dev);
            flagged_text(&mut text, &flagged(dev), all);
        }
    }
    let (e, w) = (report.errors(), report.warnings());
    let _ = writeln!(text, "\nfindings: {e} error(s), {w} warning(s)");
    let shown = if all {
        report.findings.len()
    } else {
        report.findings.len().min(20)
    };
    for f in &report.findings[..shown] {
        let _ = writeln!(text, "  {}", report.finding_line(f));
    }
    if shown < report.findings.len() {
        let _ = writeln!(
            text,
            "  … {} more (--all lists every finding)",
            report.findings.len() - shown
        );
    }
    round_trip_text(&mut text, report, all);
    text
}

fn round_trip_text(text: &mut String, report: &FileReport, all: bool) {
    let Some(diffs) = &report.round_trip else {
        return;
    };
    if diffs.is_empty() {
        let _ = writeln!(text, "round trip: equal");
        return;
    }
    let _ = writeln!(text, "round trip: {} difference(s)", diffs.len());
    let shown = if all {
        diffs.len()
    } else {
        diffs.len().min(20)
    };
    for d in &diffs[..shown] {
        let _ = writeln!(text, "  {d}");
    }
    if shown < diffs.len() {
        let _ = writeln!(text, "  … {} more", diffs.len() - shown);
    }
}

/// The one-screen summary of a device.
fn summary(text: &mut String, dev: &DeviceDescription) {
    let id = &dev.identity;
    let d = &dev.dictionary;
    let subs: usize = d.objects().map(|o| o.subs.len()).sum();
    let count =
        |r: std::ops::RangeInclusive<u16>| d.objects().filter(|o| r.contains(&o.index)).count();
    let _ = writeln!(text, "\n{}", crate::device_name(dev));
    if !id.order_code.is_empty() && !id.product_name.is_empty() && id.product_name != id.order_code
    {
        let _ = writeln!(text, "  name         {}", id.product_name);
    }
    let _ = writeln!(
        text,
        "  vendor       0x{:08X} {}",
        id.vendor_id, id.vendor_name
    );
    let _ = writeln!(
        text,
        "  product code 0x{:08X}  revision 0x{:08X}",
        id.product_code, id.revision
    );
    let _ = writeln!(
        text,
        "  dictionary   {} objects, {} entries: {} communication, {} manufacturer, {} profile",
        d.len(),
        subs,
        count(0x1000..=0x1FFF),
        count(0x2000..=0x5FFF),
        count(0x6000..=0xFFFF)
    );
    let _ = writeln!(
        text,
        "  PDO mappings {} receive, {} transmit",
        count(0x1600..=0x17FF),
        count(0x1A00..=0x1BFF)
    );
    if let Some(ec) = &dev.ethercat {
        let modes: Vec<&str> = ec.op_modes.iter().map(|m| m.name.as_str()).collect();
        let _ = writeln!(
            text,
            "  EtherCAT     {} SMs, {} RxPDO, {} TxPDO, op modes: {}",
            ec.sync_managers.len(),
            ec.rx_pdos.len(),
            ec.tx_pdos.len(),
            if modes.is_empty() {
                "none".to_string()
            } else {
                modes.join(", ")
            }
        );
    }
    if let Some(c) = &dev.commissioning {
        let node = c
            .node_id
            .map_or_else(|| "unconfigured".to_string(), |id| id.to_string());
        // `Baudrate=0` (or none) in a DCF: the bit rate is left to the network.
        let rate = match c.baud_rate {
            0 => "not given".to_string(),
            r => format!("{r} kbit/s"),
        };
        let _ = writeln!(text, "  node-ID      {node}  bit rate {rate}");
    }
}

/// The entries a device flags with `ObjFlags`, and what a tool makes of them: the first 10, every
/// one with `all`.
fn flagged_text(text: &mut String, flagged: &[Flagged], all: bool) {
    if flagged.is_empty() {
        return;
    }
    let with = |bit: u32| flagged.iter().filter(|f| f.flags & bit != 0).count();
    let n = flagged.len();
    let _ = writeln!(
        text,
        "  ObjFlags     {n} {} flagged: {} refuse write on download (sdo-tool apply does not write \
         them), {} refuse read on scan (sdo-tool dump does not read them)",
        if n == 1 { "entry" } else { "entries" },
        with(1),
        with(2)
    );
    let shown = if all {
        flagged.len()
    } else {
        flagged.len().min(10)
    };
    for f in &flagged[..shown] {
        let _ = writeln!(
            text,
            "    0x{:04X}:{:02X} {}: {}",
            f.index,
            f.sub,
            f.name,
            od::object::ObjFlags::from_bits(f.flags)
        );
    }
    if shown < flagged.len() {
        let _ = writeln!(
            text,
            "    … {} more (--all lists every one)",
            flagged.len() - shown
        );
    }
}

/// One line of a batch check: file, format, devices, objects, errors, warnings, time; and the
/// round trip when one was made.
pub fn batch_line(report: &FileReport) -> String {
    let format = report.format.map_or("?".to_string(), |f| f.to_string());
    let objects: usize = report.devices.iter().map(|d| d.objects).sum();
    let mut line = format!(
        "{}  {format}  {} device(s)  {objects} objects  {} error(s)  {} warning(s)  {:.1} ms",
        report.path.display(),
        report.devices.len(),
        report.errors(),
        report.warnings(),
        report.milliseconds
    );
    match &report.round_trip {
        Some(d) if d.is_empty() => line.push_str("  round trip equal"),
        Some(d) => {
            let _ = write!(line, "  round trip: {} difference(s)", d.len());
        }
        None => {}
    }
    line
}

/// The text of a batch check: a line per file (with its errors and round-trip differences, at most
/// three of each unless `all`, or every finding with `all`) and a summary.
pub fn text_batch(reports: &[FileReport], all: bool, total_ms: f64) -> String {
    let mut text = String::new();
    for r in reports {
        let _ = writeln!(text, "{}", batch_line(r));
        let listed: Vec<&Located> = r
            .findings
            .iter()
            .filter(|f| all || f.finding.severity == Severity::Error)
            .collect();
        let shown = if all {
            listed.len()
        } else {
            listed.len().min(3)
        };
        for f in &listed[..shown] {
            let _ = writeln!(text, "    {}", r.finding_line(f));
        }
        if shown < listed.len() {
            let _ = writeln!(text, "    … {} more error(s)", listed.len() - shown);
        }
        if let Some(d) = &r.round_trip {
            let shown = if all { d.len() } else { d.len().min(3) };
            for line in &d[..shown] {
                let _ = writeln!(text, "    round trip: {line}");
            }
            if shown < d.len() {
                let _ = writeln!(text, "    … {} more difference(s)", d.len() - shown);
            }
        }
    }
    let s = Summary::of(reports, total_ms);
    let _ = writeln!(
        text,
        "{} file(s): {} passed, {} with errors{}; {} error(s), {} warning(s); {:.0} ms",
        s.files,
        s.passed,
        s.with_errors,
        if s.round_trip_failed > 0 {
            format!(", {} not equal after a round trip", s.round_trip_failed)
        } else {
            String::new()
        },
        s.errors,
        s.warnings,
        s.milliseconds
    );
    text
}

/// Counts over a batch.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct Summary {
    /// Files checked.
    pub files: usize,
    /// Files without errors whose round trip (when made) came back equal.
    pub passed: usize,
    /// Files with at least one error.
    pub with_errors: usize,
    /// Files whose round trip did not come back equal.
    pub round_trip_failed: usize,
    /// Errors in all files.
    pub errors: usize,
    /// Warnings in all files.
    pub warnings: usize,
    /// Time of the whole check.
    pub milliseconds: f64,
}

impl Summary {
    /// The counts of `reports`.
    pub fn of(reports: &[FileReport], milliseconds: f64) -> Summary {
        Summary {
            files: reports.len(),
            passed: reports.iter().filter(|r| r.passed()).count(),
            with_errors: reports.iter().filter(|r| r.errors() > 0).count(),
            round_trip_failed: reports
                .iter()
                .filter(|r| r.round_trip.as_ref().is_some_and(|d| !d.is_empty()))
                .count(),
            errors: reports.iter().map(FileReport::errors).sum(),
            warnings: reports.iter().map(FileReport::warnings).sum(),
            milliseconds,
        }
    }
}

#[derive(Serialize)]
struct JsonFinding<'a> {
    severity: &'static str,
    line: Option<u32>,
    column: Option<u32>,
    device: Option<&'a str>,
    index: Option<u16>,
    sub: Option<u8>,
    message: &'a str,
}

#[derive(Serialize)]
struct JsonFile<'a> {
    path: String,
    format: Option<String>,
    readable: bool,
    devices: &'a [DeviceLine],
    errors: usize,
    warnings: usize,
    milliseconds: f64,
    round_trip: Option<&'a [String]>,
    findings: Vec<JsonFinding<'a>>,
}

#[derive(Serialize)]
struct JsonReport<'a> {
    files: Vec<JsonFile<'a>>,
    summary: Summary,
}

/// The JSON document of a check: `{"files": [...], "summary": {...}}`, every finding included.
pub fn json(reports: &[FileReport], total_ms: f64) -> String {
    let files = reports
        .iter()
        .map(|r| JsonFile {
            path: r.path.display().to_string(),
            format: r.format.map(|f| f.to_string()),
            readable: !r.unreadable,
            devices: &r.devices,
            errors: r.errors(),
            warnings: r.warnings(),
            milliseconds: r.milliseconds,
            round_trip: r.round_trip.as_deref(),
            findings: r
                .findings
                .iter()
                .map(|f| JsonFinding {
                    severity: f.finding.severity.as_str(),
                    line: f.finding.position.map(|p| p.line),
                    column: f.finding.position.map(|p| p.column),
                    device: f.device.as_deref(),
                    index: f.finding.address.map(|a| a.index),
                    sub: f.finding.address.map(|a| a.sub),
                    message: &f.finding.message,
                })
                .collect(),
        })
        .collect();
    let doc = JsonReport {
        files,
        summary: Summary::of(reports, total_ms),
    };
    let mut s = serde_json::to_string_pretty(&doc).unwrap_or_else(|_| "{}".into());
    s.push('\n');
    s
}

/// The description files under `dir`, recursively, in name order: the extensions of ESI, EDS, DCF,
/// XDD/XDC/XPD files, case-insensitively. Links to folders are not followed, and at most 32 levels.
pub fn files_in(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    walk(dir, 0, &mut out)?;
    out.sort();
    Ok(out)
}

fn walk(dir: &Path, depth: usize, out: &mut Vec<PathBuf>) -> std::io::Result<()> {
    if depth > 32 {
        return Ok(());
    }
    for entry in std::fs::read_dir(dir)? {
        let entry = entry?;
        let kind = entry.file_type()?;
        let path = entry.path();
        if kind.is_dir() {
            walk(&path, depth + 1, out)?;
        } else if is_description_name(&path) {
            out.push(path);
        }
    }
    Ok(())
}

/// True for the file names description files have.
pub fn is_description_name(path: &Path) -> bool {
    const EXTENSIONS: [&str; 7] = ["xml", "esi", "eds", "dcf", "xdd", "xdc", "xpd"];
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| EXTENSIONS.iter().any(|x| x.eq_ignore_ascii_case(e)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use od::object::{AccessType, Object, SubObject};
    use od::types::DataType;

    fn device(name: &str, code: u32) -> DeviceDescription {
        let mut d = DeviceDescription::default();
        d.identity.order_code = name.into();
        d.identity.product_code = code;
        d.identity.revision = 1;
        d.dictionary.insert(Object::var(
            0x1000,
            SubObject::new("Device type", DataType::Unsigned32, AccessType::Ro),
        ));
        d
    }

    #[test]
    fn differences_pair_devices_and_name_them_when_there_are_several() {
        let one = [device("A", 1)];
        let mut changed = device("A", 1);
        changed.identity.product_name = "Alpha".into();
        assert_eq!(
            differences(&one, std::slice::from_ref(&changed)),
            vec!["~ identity product name: \"\" -> \"Alpha\""]
        );
        let two = [device("A", 1), device("B", 2)];
        assert_eq!(
            differences(&two, &[changed.clone(), device("C", 3)]),
            vec![
                "A rev 0x00000001: ~ identity product name: \"\" -> \"Alpha\"",
                "B rev 0x00000001: not read back",
                "C rev 0x00000001: read back, but not written",
            ]
        );
        assert_eq!(differences(&two, &two), Vec::<String>::new());
    }

    #[test]
    fn a_round_trip_lists_what_its_format_does_not_keep() {
        let mut d = device("A", 1);
        d.dictionary.object_mut(0x1000).unwrap().description = Some("kind".into());
        d.file_info.creation_date = "2024-05-06".into();
        // An EDS has no object descriptions; an XDD has. The CAN information an EDS has or has not
        // comes back as it was.
        assert_eq!(
            round_trip(Format::Eds, std::slice::from_ref(&d)),
            vec!["~ 0x1000 description: \"kind\" -> none"]
        );
        d.can = Some(od::device::CanInfo::default());
        assert_eq!(
            round_trip(Format::Eds, std::slice::from_ref(&d)),
            vec!["~ 0x1000 description: \"kind\" -> none"]
        );
        // An XDD keeps the revision in 0x1018:03 only; the EDS written of a CANopen file is checked for
        // errors only.
        assert_eq!(
            round_trip(Format::Xdd, std::slice::from_ref(&d)),
            vec!["~ identity revision: 0x00000001 -> 0x00000000"]
        );
        d.identity.revision = 0;
        assert_eq!(
            round_trip(Format::Xdd, std::slice::from_ref(&d)),
            Vec::<String>::new()
        );
        assert_eq!(round_trip(Format::Esi, &[]), Vec::<String>::new());
        // Several devices, each named; an ESI gives every device its EtherCAT parts.
        let two = [device("A", 1), device("B", 2)];
        assert_eq!(
            round_trip(Format::Esi, &two),
            vec![
                "A rev 0x00000001: + EtherCAT",
                "B rev 0x00000001: + EtherCAT"
            ]
        );
    }
}
