//! Generation: each slave's concise DCF and the master's objects, as dcfgen makes them.

use crate::file::{IdentityKeys, SlaveFile};
use od::DeviceDescription;

use crate::bus::{Bus, Ctx, NetError, Number, Section};
use crate::concise;
use crate::master::Master;
use crate::slave::{int_value, read_pdo, Cx, Pdo, Slave};
use crate::yaml::{Kind, Node};

/// What generation made: the files by name and the warnings.
#[derive(Debug, Clone, PartialEq)]
pub struct Generated {
    /// The files: each slave's `NAME.bin`, `master.dcf` and, when it has entries, `master.bin`.
    pub files: Vec<(String, Vec<u8>)>,
    /// Warnings, one line each.
    pub warnings: Vec<String>,
    /// The slaves, as generated.
    pub slaves: Vec<Slave>,
    /// The master, as generated.
    pub master: Master,
}

/// How to generate.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct GenOptions {
    /// Write the remote PDO mapping objects (0x5800..0x5FFF) into `master.dcf` (dcfgen `-r`).
    pub remote_pdo: bool,
    /// Take a slave description its strict reading ([`crate::lint`]) refuses as it is (dcfgen `-S`).
    pub no_strict: bool,
}

/// Generates the files for `bus`. `load` gives the description of a slave's `dcf` (the text of the
/// key, relative to the YAML's folder) or why there is none; `env` gives the environment variables
/// `$VAR` in a `dcf_path` stands for.
pub fn generate(
    bus: &Bus,
    load: &mut dyn FnMut(&str) -> Result<SlaveFile, String>,
    env: &dyn Fn(&str) -> Option<String>,
    opts: GenOptions,
) -> Result<Generated, NetError> {
    let mut cx = Cx {
        ctx: Ctx { file: &bus.file },
        next_cob_id: 0x680,
        warnings: Vec::new(),
        no_strict: opts.no_strict,
    };
    let mut slaves = Vec::new();
    for section in &bus.slaves {
        let slave = from_config(&mut cx, bus, section, load, env)?;
        if slave.node_id != 255 {
            slaves.push(slave);
        } else {
            let name = &section.name;
            cx.warnings
                .push(format!("{name}: ignoring slave with unconfigured node-ID"));
        }
    }
    let master = Master::from_config(&mut cx, bus, &mut slaves)?;
    let mut files = Vec::new();
    for slave in &slaves {
        if !slave.sdo.is_empty() {
            files.push((format!("{}.bin", slave.name), concise::encode(&slave.sdo)));
        }
    }
    files.push((
        "master.dcf".into(),
        master.render(&slaves, opts.remote_pdo).into_bytes(),
    ));
    if !master.sdo.is_empty() {
        files.push(("master.bin".into(), concise::encode(&master.sdo)));
    }
    Ok(Generated {
        files,
        warnings: cx.warnings,
        slaves,
        master,
    })
}

/// Python's `os.path.expandvars`: `$NAME` and `${NAME}` replaced where `env` knows the name.
pub fn expand_vars(text: &str, env: &dyn Fn(&str) -> Option<String>) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        let after = &rest[at + 1..];
        let (name, tail) = if let Some(b) = after.strip_prefix('{') {
            match b.find('}') {
                Some(end) => (&b[..end], &b[end + 1..]),
                None => ("", after),
            }
        } else {
            let end = after
                .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
                .unwrap_or(after.len());
            (&after[..end], &after[end..])
        };
        match (!name.is_empty()).then(|| env(name)).flatten() {
            Some(value) => {
                out.push_str(&value);
                rest = tail;
            }
            None => {
                out.push('$');
                rest = after;
            }
        }
    }
    out.push_str(rest);
    out
}

fn key(section: &Section, k: &str) -> String {
    format!("{}.{k}", section.name)
}

/// Reads one slave section and makes its entries, in dcfgen's order.
fn from_config(
    cx: &mut Cx,
    bus: &Bus,
    section: &Section,
    load: &mut dyn FnMut(&str) -> Result<SlaveFile, String>,
    env: &dyn Fn(&str) -> Option<String>,
) -> Result<Slave, NetError> {
    let ctx = cx.ctx;
    let empty = Node {
        line: section.line,
        kind: Kind::Null,
    };
    let cfg = section.node.as_ref().unwrap_or(&empty);
    let get = |k: &str| ctx.get(cfg, &section.name, k);
    let node_id = match get("node_id")? {
        Some(v) => Some(ctx.int_in(v, &key(section, "node_id"), 0, 255)? as u8),
        None => None,
    };
    let Some(dcf) = get("dcf")? else {
        return Err(ctx.error(section.line, &section.name, "no dcf is given"));
    };
    let dcf_key = key(section, "dcf");
    let dcf_text = ctx.string(dcf, &dcf_key)?;
    let file = load(&dcf_text).map_err(|m| ctx.error(dcf.line, &dcf_key, m))?;
    let keys = file.keys;
    cx.warnings.extend(file.lint.warnings.iter().cloned());
    if !file.lint.ok && !cx.no_strict {
        let first = file.lint.warnings.first().map_or("", String::as_str);
        let m = format!("invalid DCF: {dcf_text} ({first}; -S takes it as it is)");
        return Err(ctx.error(dcf.line, &dcf_key, m));
    }
    let mut desc = file.description;
    let node_id = node_id.or(desc.node_id()).map_or(255, u32::from);
    if !(1..=127).contains(&node_id) && node_id != 255 {
        cx.warnings
            .push(format!("invalid node-ID specified: {node_id}"));
    }
    if node_id == 255 {
        if let Some(at) = node_relative(&desc) {
            let m = format!("{at} is given as $NODEID+…, and the slave has no node_id");
            return Err(ctx.error(section.line, &section.name, m));
        }
    }
    desc.set_node_id(Some(node_id as u8));
    let mut slave = identity(section, desc, keys, node_id, &mut cx.warnings)?
        .map_err(|m| ctx.error(dcf.line, &dcf_key, m))?;
    slave.dcf = (dcf_text.clone(), dcf.line);
    slave.key_lines = key_lines(ctx, cfg, &section.name)?;
    slave.dcf_path = match get("dcf_path")? {
        Some(v) => ctx.string(v, &key(section, "dcf_path"))?,
        None => bus.options.dcf_path.clone(),
    };
    slave.dcf_path = expand_vars(&slave.dcf_path, env);
    let u32_of = |k: &str| -> Result<Option<(u32, &Node)>, NetError> {
        match get(k)? {
            Some(v) => Ok(Some((
                ctx.int_in(v, &key(section, k), 0, u32::MAX.into())? as u32,
                v,
            ))),
            None => Ok(None),
        }
    };
    for (k, field, what) in [
        ("revision_number", 3, "revision number"),
        ("serial_number", 4, "serial number"),
    ] {
        if let Some((v, _)) = u32_of(k)? {
            let old = if field == 3 {
                &mut slave.revision_number
            } else {
                &mut slave.serial_number
            };
            if *old != 0 && *old != v {
                cx.warnings.push(format!(
                    "{}: specified {what} differs from DCF",
                    section.name
                ));
            }
            *old = v;
        }
    }
    // dcfgen compares with 0x100 whatever 0x1012 holds.
    if let Some((v, n)) = u32_of("time_cob_id")? {
        if v != 0x100 {
            communication(cx, &mut slave, n, &key(section, "time_cob_id"), 0x1012, v)?;
        }
    }
    slave.heartbeat_multiplier = match get("heartbeat_multiplier")? {
        Some(v) => ctx.float(v, &key(section, "heartbeat_multiplier"))?,
        None => bus.options.heartbeat_multiplier,
    };
    if let Some(v) = get("heartbeat_consumer")? {
        slave.heartbeat_consumer = ctx.truth(v);
    }
    if let Some((v, n)) = u32_of("heartbeat_producer")? {
        if v != slave.heartbeat_producer {
            communication(
                cx,
                &mut slave,
                n,
                &key(section, "heartbeat_producer"),
                0x1017,
                v,
            )?;
        }
        slave.heartbeat_producer = v;
    }
    slave.retry_factor = match get("retry_factor")? {
        Some(v) => ctx.int(v, &key(section, "retry_factor"))?,
        None => bus.options.retry_factor,
    };
    if let Some((v, n)) = u32_of("guard_time")? {
        if v != slave.guard_time {
            communication(cx, &mut slave, n, &key(section, "guard_time"), 0x100C, v)?;
        }
        slave.guard_time = v;
    }
    if let Some((v, n)) = u32_of("life_time_factor")? {
        if v != slave.life_time_factor {
            communication(
                cx,
                &mut slave,
                n,
                &key(section, "life_time_factor"),
                0x100D,
                v,
            )?;
        }
        slave.life_time_factor = v;
    }
    if slave.guard_time != 0 && slave.life_time_factor != 0 && slave.heartbeat_producer != 0 {
        cx.warnings
            .push("Cannot use heartbeat protocol and node guarding protocol simultaneously".into());
        slave.guard_time = 0;
        slave.life_time_factor = 0;
    }
    error_behavior(cx, &mut slave, section, get("error_behavior")?)?;
    pdos(cx, &mut slave, section, get("rpdo")?, false)?;
    pdos(cx, &mut slave, section, get("tpdo")?, true)?;
    nmt(cx, &mut slave, section, cfg)?;
    Ok(slave)
}

/// The lines of the keys a boot error names, where the section gives them.
fn key_lines(ctx: Ctx, cfg: &Node, name: &str) -> Result<Vec<(&'static str, usize)>, NetError> {
    let mut lines = Vec::new();
    for k in [
        "heartbeat_producer",
        "software_version",
        "revision_number",
        "serial_number",
    ] {
        if let Some(v) = ctx.get(cfg, name, k)? {
            lines.push((k, v.line));
        }
    }
    Ok(lines)
}

/// The first entry dcfgen reads whose value is relative to the node-ID (`$NODEID+…`): dcfgen
/// cannot read it for a slave without one.
fn node_relative(desc: &DeviceDescription) -> Option<String> {
    let read = |index: u16| {
        matches!(
            index,
            0x1000 | 0x100C | 0x100D | 0x1012 | 0x1014 | 0x1016 | 0x1017 | 0x1018 | 0x1029
        ) || (0x1400..0x1C00).contains(&index)
    };
    desc.dictionary
        .objects()
        .filter(|o| read(o.index))
        .find_map(|o| {
            let relative = |s: &od::SubObject| {
                s.value_plus_node_id || s.default.as_ref().is_some_and(|d| d.plus_node_id)
            };
            o.subs
                .iter()
                .find(|(_, s)| relative(s))
                .map(|(sub, _)| format!("0x{:04X}/{sub}", o.index))
        })
}

/// Writes `value` to `index` when the slave has it, else warns.
fn communication(
    cx: &mut Cx,
    slave: &mut Slave,
    node: &Node,
    key: &str,
    index: u16,
    value: u32,
) -> Result<(), NetError> {
    if slave.desc.dictionary.object(index).is_some() {
        slave.push(cx, node, key, (index, 0), Number::Int(value.into()))
    } else {
        cx.warnings.push(format!(
            "{}: object 0x{index:04X} does not exist",
            slave.name
        ));
        Ok(())
    }
}

/// The slave as its description gives it.
fn identity(
    section: &Section,
    desc: DeviceDescription,
    keys: IdentityKeys,
    node_id: u32,
    warnings: &mut Vec<String>,
) -> Result<Result<Slave, String>, NetError> {
    let dict = &desc.dictionary;
    let val = |index: u16, sub: u8| {
        dict.object(index)
            .and_then(|o| int_value(o, sub))
            .map(|v| v as u32)
    };
    let Some(device_type) = val(0x1000, 0) else {
        return Ok(Err("object 0x1000 does not exist".into()));
    };
    let Some(vendor) = val(0x1018, 1) else {
        return Ok(Err("sub-object 0x1018/1 does not exist".into()));
    };
    let mut pick = |given: bool, described: u32, own: u32, (key, word): (&str, &str)| {
        if given && own != 0 && own != described {
            warnings.push(format!("{key} differs from {word} in identity object"));
        }
        if given {
            described
        } else {
            own
        }
    };
    let id = &desc.identity;
    let lss = desc
        .commissioning
        .as_ref()
        .map_or(0, |c| c.lss_serial_number);
    let mut error_behavior = Vec::new();
    if let Some(o) = dict.object(0x1029) {
        for (&sub, _) in o.subs.iter().filter(|(s, _)| **s != 0) {
            error_behavior.push((sub, int_value(o, sub).unwrap_or(0)));
        }
    }
    let mut rpdo = Vec::new();
    let mut tpdo = Vec::new();
    for i in 0..512u16 {
        for (base, list) in [(0x1400, &mut rpdo), (0x1800, &mut tpdo)] {
            if dict.object(base + i).is_some() {
                list.push((
                    u32::from(i) + 1,
                    read_pdo(&desc, base + i).map_err(|m| m.to_string()),
                ));
            }
        }
    }
    let unwrap = |list: Vec<(u32, Result<Pdo, String>)>| {
        list.into_iter()
            .map(|(n, p)| p.map(|p| (n, p)))
            .collect::<Result<Vec<_>, _>>()
    };
    let (rpdo, tpdo) = match (unwrap(rpdo), unwrap(tpdo)) {
        (Ok(r), Ok(t)) => (r, t),
        (Err(e), _) | (_, Err(e)) => return Ok(Err(e)),
    };
    Ok(Ok(Slave {
        name: section.name.clone(),
        node_id,
        line: section.line,
        dcf: (String::new(), section.line),
        device_type,
        vendor_id: pick(
            keys.vendor,
            id.vendor_id,
            vendor,
            ("VendorNumber in [DeviceInfo]", "vendor-ID"),
        ),
        product_code: pick(
            keys.product,
            id.product_code,
            val(0x1018, 2).unwrap_or(0),
            ("ProductNumber in [DeviceInfo]", "product code"),
        ),
        revision_number: pick(
            keys.revision,
            id.revision,
            val(0x1018, 3).unwrap_or(0),
            ("RevisionNumber in [DeviceInfo]", "revision number"),
        ),
        serial_number: pick(
            keys.serial,
            lss,
            val(0x1018, 4).unwrap_or(0),
            ("LSS_SerialNumber in [DeviceComissioning]", "serial number"),
        ),
        emcy_cob_id: val(0x1014, 0).unwrap_or(0x8000_0000),
        heartbeat_multiplier: 3.0,
        heartbeat_consumer: false,
        heartbeat_producer: val(0x1017, 0).unwrap_or(0),
        retry_factor: 3,
        guard_time: val(0x100C, 0).unwrap_or(0),
        life_time_factor: val(0x100D, 0).unwrap_or(0),
        boot: true,
        mandatory: false,
        reset_communication: true,
        software_file: String::new(),
        software_version: 0,
        configuration_file: String::new(),
        restore_configuration: 0,
        dcf_path: String::new(),
        rpdo,
        tpdo,
        error_behavior,
        sdo: Vec::new(),
        sdo_origin: Vec::new(),
        key_lines: Vec::new(),
        desc,
    }))
}

fn error_behavior(
    cx: &mut Cx,
    slave: &mut Slave,
    section: &Section,
    node: Option<&Node>,
) -> Result<(), NetError> {
    let Some(node) = node else { return Ok(()) };
    let k = key(section, "error_behavior");
    for (sk, v) in node.entries() {
        let sub = cx.ctx.int_in(sk, &k, 0, 255)? as u8;
        match slave
            .error_behavior
            .iter()
            .find(|(s, _)| *s == sub)
            .map(|(_, v)| *v)
        {
            Some(old) => {
                let value = cx.ctx.int(v, &format!("{k}.{sub}"))?;
                if value != old {
                    slave.push(cx, v, &k, (0x1029, sub), Number::Int(value))?;
                }
            }
            None => cx.warnings.push(format!(
                "{}: sub-object 0x1029/{sub} does not exist",
                slave.name
            )),
        }
    }
    Ok(())
}

fn pdos(
    cx: &mut Cx,
    slave: &mut Slave,
    section: &Section,
    node: Option<&Node>,
    tpdo: bool,
) -> Result<(), NetError> {
    let (what, base, name) = if tpdo {
        ("tpdo", 0x1800, "Transmit-PDO")
    } else {
        ("rpdo", 0x1400, "Receive-PDO")
    };
    if let Some(node) = node {
        let k = key(section, what);
        for (nk, cfg) in node.entries() {
            let n = cx.ctx.int(nk, &k)?;
            let list = if tpdo { &slave.tpdo } else { &slave.rpdo };
            let Some(pos) = list.iter().position(|(i, _)| i128::from(*i) == n) else {
                return Err(cx.ctx.error(
                    nk.line,
                    &k,
                    format!("{}: {name} {n} not available", slave.name),
                ));
            };
            let mut pdo = list[pos].1.clone();
            crate::pdo::configure(
                cx,
                slave,
                &mut pdo,
                base + n as u16 - 1,
                cfg,
                &format!("{k}.{n}"),
            )?;
            let list = if tpdo {
                &mut slave.tpdo
            } else {
                &mut slave.rpdo
            };
            list[pos].1 = pdo;
        }
    }
    let list = if tpdo {
        &mut slave.tpdo
    } else {
        &mut slave.rpdo
    };
    list.retain(|(_, p)| p.cob_id & 0x8000_0000 == 0 && !p.mapping.is_empty());
    Ok(())
}

fn nmt(cx: &mut Cx, slave: &mut Slave, section: &Section, cfg: &Node) -> Result<(), NetError> {
    let ctx = cx.ctx;
    let get = |k: &str| ctx.get(cfg, &section.name, k);
    if let Some(v) = get("boot")? {
        slave.boot = ctx.truth(v);
    }
    if let Some(v) = get("mandatory")? {
        slave.mandatory = ctx.truth(v);
    }
    if let Some(v) = get("reset_communication")? {
        slave.reset_communication = ctx.truth(v);
    }
    if let Some(v) = get("software_file")? {
        slave.software_file = ctx.string(v, &key(section, "software_file"))?;
    }
    let dict = &slave.desc.dictionary;
    if let Some(v) = get("software_version")? {
        slave.software_version =
            ctx.int_in(v, &key(section, "software_version"), 0, u32::MAX.into())? as u32;
        if dict.object(0x1F56).and_then(|o| o.sub(1)).is_none() {
            cx.warnings.push(format!(
                "{}: sub-object 0x1F56/1 does not exist",
                slave.name
            ));
        }
    }
    if let Some(v) = get("restore_configuration")? {
        let r = ctx.int_in(v, &key(section, "restore_configuration"), 0, 255)? as u32;
        slave.restore_configuration = r;
        if dict.object(0x1011).and_then(|o| o.sub(r as u8)).is_none() {
            cx.warnings.push(format!(
                "{}: sub-object 0x1011/{r} does not exist",
                slave.name
            ));
        }
    }
    if let Some(list) = get("sdo")? {
        let k = key(section, "sdo");
        let Kind::Seq(items) = &list.kind else {
            return Err(ctx.error(list.line, &k, "is no list"));
        };
        for item in items {
            let field = |f: &str| ctx.get(item, &k, f);
            let Some(index) = field("index")? else {
                return Err(ctx.error(item.line, &k, "an entry without index"));
            };
            let index = ctx.int_in(index, &format!("{k}.index"), 0, 0xFFFF)? as u16;
            let sub = match field("sub_index")? {
                Some(s) => ctx.int_in(s, &format!("{k}.sub_index"), 0, 255)? as u8,
                None => 0,
            };
            // dcfgen takes int() of the value, for a REAL32 or REAL64 entry too (1.5 writes 1.0).
            let value = match field("value")? {
                Some(v) => Number::Int(ctx.int(v, &format!("{k}.value"))?),
                None => Number::Int(0),
            };
            slave.push(cx, item, &k, (index, sub), value)?;
        }
    }
    if !slave.sdo.is_empty() {
        let sep = if slave.dcf_path.is_empty() || slave.dcf_path.ends_with('/') {
            ""
        } else {
            "/"
        };
        slave.configuration_file = format!("{}{sep}{}.bin", slave.dcf_path, slave.name);
    }
    Ok(())
}
