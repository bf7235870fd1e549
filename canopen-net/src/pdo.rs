//! A slave's PDO as the bus description configures it (`rpdo:`/`tpdo:` entries), with the entries
//! dcfgen writes for it: invalidate the COB-ID, the parameters that changed, the mapping, then the
//! COB-ID again.

use crate::bus::{NetError, Number};
use crate::slave::{bits, Cx, Mapped, Pdo, Slave};
use crate::yaml::{Kind, Node};

/// Configures `pdo` (communication parameter `comm`) of `slave` from `cfg`, adding its entries.
pub(crate) fn configure(
    cx: &mut Cx,
    slave: &mut Slave,
    pdo: &mut Pdo,
    comm: u16,
    cfg: &Node,
    key: &str,
) -> Result<(), NetError> {
    let ctx = cx.ctx;
    let tpdo = comm & 0xFE00 == 0x1800;
    let get = |k: &str| ctx.get(cfg, key, k);
    let int = |n: &Node, k: &str| {
        ctx.int_in(n, &format!("{key}.{k}"), 0, u32::MAX.into())
            .map(|v| v as u32)
    };
    let original = pdo.cob_id;
    if let Some(v) = get("cob_id")? {
        if v.kind == Kind::Str("auto".into()) {
            let i = u32::from(comm & 0x01FF);
            pdo.cob_id = if i < 4 {
                (i + 1) * 0x100 + if tpdo { 0x80 } else { 0x100 } + slave.node_id
            } else {
                let id = cx.next_cob_id;
                if id >= 0x6E0 {
                    return Err(ctx.error(
                        v.line,
                        &format!("{key}.cob_id"),
                        "no valid 11-bit COB-IDs remaining",
                    ));
                }
                cx.next_cob_id = id + 1;
                id
            };
        } else {
            pdo.cob_id = int(v, "cob_id")?;
        }
    }
    if original != pdo.cob_id | 0x8000_0000 {
        slave.push(
            cx,
            cfg,
            key,
            (comm, 1),
            Number::Int((pdo.cob_id | 0x8000_0000).into()),
        )?;
    }
    if pdo.cob_id & 0x8000_0000 != 0 {
        return Ok(());
    }
    if let Some(v) = get("transmission")? {
        let t = int(v, "transmission")?;
        if t != pdo.transmission_type {
            pdo.transmission_type = t;
            slave.push(cx, v, key, (comm, 2), Number::Int(t.into()))?;
        }
    }
    if let Some(v) = get("inhibit_time")? {
        let t = int(v, "inhibit_time")?;
        if t != pdo.inhibit_time {
            pdo.inhibit_time = t;
            if tpdo {
                slave.push(cx, v, key, (comm, 3), Number::Int(t.into()))?;
            }
        }
    }
    let mut event_timer = None;
    if let Some(v) = get("event_timer")? {
        let t = int(v, "event_timer")?;
        event_timer = Some(t);
        if t != pdo.event_timer {
            pdo.event_timer = t;
            if tpdo {
                slave.push(cx, v, key, (comm, 5), Number::Int(t.into()))?;
            }
        }
    }
    if let Some(v) = get("event_deadline")? {
        let t = int(v, "event_deadline")?;
        if t != pdo.event_deadline {
            pdo.event_deadline = t;
            if !tpdo {
                // dcfgen writes the event timer given beside it, and fails without one.
                let Some(timer) = event_timer else {
                    return Err(ctx.error(
                        v.line,
                        &format!("{key}.event_deadline"),
                        "an event deadline needs an event_timer beside it",
                    ));
                };
                slave.push(cx, v, key, (comm, 5), Number::Int(timer.into()))?;
            }
        }
    }
    if let Some(v) = get("sync_start")? {
        let t = int(v, "sync_start")?;
        if t != pdo.sync_start {
            pdo.sync_start = t;
            if tpdo {
                slave.push(cx, v, key, (comm, 6), Number::Int(t.into()))?;
            }
        }
    }
    if let Some(m) = get("mapping")? {
        mapping(cx, slave, pdo, comm, m, &format!("{key}.mapping"))?;
    }
    let enabled = match get("enabled")? {
        Some(v) => ctx.truth(v),
        None => true,
    };
    if enabled {
        slave.push(cx, cfg, key, (comm, 1), Number::Int(pdo.cob_id.into()))?;
    }
    Ok(())
}

fn mapping(
    cx: &mut Cx,
    slave: &mut Slave,
    pdo: &mut Pdo,
    comm: u16,
    list: &Node,
    key: &str,
) -> Result<(), NetError> {
    let ctx = cx.ctx;
    let items: &[Node] = match &list.kind {
        Kind::Seq(items) => items,
        Kind::Null => &[],
        _ => return Err(ctx.error(list.line, key, "is no list")),
    };
    let map = comm + 0x200;
    if pdo.n > 0 || !items.is_empty() {
        pdo.n = 0;
        pdo.mapping.clear();
        slave.push(cx, list, key, (map, 0), Number::Int(0))?;
    }
    let mut size = 0;
    for (n, item) in (1u32..).zip(items) {
        let Some(index) = ctx.get(item, key, "index")? else {
            return Err(ctx.error(item.line, key, "an entry without index"));
        };
        let index = ctx.int_in(index, &format!("{key}.index"), 0, 0xFFFF)? as u16;
        let sub = match ctx.get(item, key, "sub_index")? {
            Some(s) => ctx.int_in(s, &format!("{key}.sub_index"), 0, 255)? as u8,
            None => 0,
        };
        let found = (index >= 0x1000)
            .then(|| slave.desc.dictionary.object(index).and_then(|o| o.sub(sub)))
            .flatten()
            .cloned();
        let Some(s) = found else {
            let m = format!(
                "{}: sub-object 0x{index:04X}/{sub} does not exist",
                slave.name
            );
            return Err(ctx.error(item.line, key, m));
        };
        if !s.pdo.any() {
            cx.warnings.push(format!(
                "{}: sub-object 0x{index:04X}/{sub} does not support PDO mapping",
                slave.name
            ));
        }
        let Some(b) = bits(s.data_type) else {
            let m = format!(
                "{}: sub-object 0x{index:04X}/{sub} is a {:?}, which no PDO maps",
                slave.name, s.data_type
            );
            return Err(ctx.error(item.line, key, m));
        };
        size += b;
        let value = (u32::from(index) << 16) | (u32::from(sub) << 8) | (b & 0xFF);
        pdo.mapping.push((
            n,
            Mapped {
                index,
                sub,
                data_type: s.data_type.index(),
                bits: b,
                name: s.name.clone(),
            },
        ));
        slave.push(cx, item, key, (map, n as u8), Number::Int(value.into()))?;
    }
    if size > 64 {
        let kind = if comm >= 0x1800 { "TPDO" } else { "RPDO" };
        cx.warnings.push(format!(
            "{}: {kind} {} mapping exceeds 64 bits",
            slave.name,
            (comm & 0x1FF) + 1
        ));
    }
    pdo.n = pdo.mapping.len() as u32;
    if pdo.n > 0 {
        slave.push(cx, list, key, (map, 0), Number::Int(pdo.n.into()))?;
    }
    Ok(())
}
