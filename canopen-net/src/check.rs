//! What is wrong with a bus description, every problem at once, before anything is sent.

use crate::file::SlaveFile;

use crate::bus::{Bus, NetError};
use crate::gen::{generate, GenOptions};

/// The problems of `bus`, one per slave that cannot be generated (missing or unreadable DCF, an entry
/// or a mapping its description cannot take, …), then node-IDs used twice, then the master's own;
/// and the warnings generation gives. `load`, `env` and `opts` are as for [`generate`].
pub fn check(
    bus: &Bus,
    load: &mut dyn FnMut(&str) -> Result<SlaveFile, String>,
    env: &dyn Fn(&str) -> Option<String>,
    opts: GenOptions,
) -> (Vec<NetError>, Vec<String>) {
    let mut errors = Vec::new();
    let mut warnings = Vec::new();
    let mut nodes: Vec<(u32, &str, usize)> = Vec::new();
    for section in &bus.slaves {
        let alone = Bus {
            slaves: vec![section.clone()],
            ..bus.clone()
        };
        match generate(&alone, load, env, opts) {
            Ok(g) => {
                warnings.extend(g.warnings);
                if let Some(s) = g.slaves.first() {
                    let clash = nodes.iter().find(|(n, _, _)| *n == s.node_id);
                    if let Some((_, other, _)) = clash {
                        errors.push(NetError {
                            file: bus.file.clone(),
                            line: section.line,
                            key: section.name.clone(),
                            message: format!("node-ID {} is {other}'s too", s.node_id),
                        });
                    }
                    nodes.push((s.node_id, &section.name, section.line));
                }
            }
            Err(e) => errors.push(e),
        }
    }
    let empty = Bus {
        slaves: Vec::new(),
        ..bus.clone()
    };
    match generate(&empty, load, env, opts) {
        Err(e) => errors.push(e),
        Ok(_) => {
            let ctx = crate::bus::Ctx { file: &bus.file };
            let node = bus.master.node.as_ref().and_then(|m| m.get("node_id"));
            let id = node
                .and_then(|(_, v)| ctx.int(v, "master.node_id").ok())
                .unwrap_or(255);
            if let Some((_, name, _)) = nodes.iter().find(|(n, _, _)| i128::from(*n) == id) {
                let line = node.map_or(bus.master.line, |(k, _)| k.line);
                errors.push(ctx.error(
                    line,
                    "master.node_id",
                    format!("node-ID {id} is {name}'s too"),
                ));
            }
        }
    }
    (errors, warnings)
}
