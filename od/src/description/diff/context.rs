//! The comparison's context: where it is and what it found ([`Cx`]), how the parts of a list pair
//! ([`Key`], [`List`]), and how values are shown.

use std::collections::HashMap;
use std::fmt;

use super::{Change, Difference, Shown, Step};

/// Where the comparison is and what it found.
pub(super) struct Cx<'o> {
    path: Vec<Step>,
    out: &'o mut Vec<Difference>,
}

/// How the parts of a list are told apart.
pub(super) enum Key<T> {
    /// By position, numbered from the given first number.
    Position(usize),
    /// By a key (an index, a name); parts with equal keys pair in their order. A change of the order of
    /// the parts both have is reported as `order` (`RxPdo order`).
    By {
        /// The key of a part.
        key: fn(&T) -> String,
        /// The field that reports a change of order.
        order: &'static str,
    },
}

/// A list of parts of one kind.
pub(super) struct List<T> {
    /// The kind, the first word of each part's step (`RxPdo`).
    pub(super) kind: &'static str,
    /// How parts pair.
    pub(super) key: Key<T>,
    /// The name a part only one side has is reported with.
    pub(super) name: fn(&T) -> String,
    /// Compares two paired parts.
    pub(super) compare: fn(&mut Cx<'_>, &T, &T),
}

impl<'o> Cx<'o> {
    pub(super) fn new(out: &'o mut Vec<Difference>) -> Cx<'o> {
        Cx {
            path: Vec::new(),
            out,
        }
    }

    pub(super) fn push(&mut self, step: Option<Step>, change: Change) {
        let mut path = self.path.clone();
        path.extend(step);
        self.out.push(Difference { path, change });
    }

    /// Runs `f` one step further down.
    pub(super) fn within(&mut self, step: Step, f: impl FnOnce(&mut Cx<'_>)) {
        self.path.push(step);
        f(self);
        self.path.pop();
    }

    /// Reports `field` when `differ`, showing the values with `show`; where both show the same text the
    /// values are shown as the model holds them, by `held`.
    pub(super) fn report<T: ?Sized>(
        &mut self,
        field: &'static str,
        differ: bool,
        (a, b): (&T, &T),
        show: impl Fn(&T) -> Shown,
        held: impl Fn(&T) -> String,
    ) {
        if !differ {
            return;
        }
        let (mut x, mut y) = (show(a), show(b));
        if x == y {
            x = Shown::Plain(held(a));
            y = Shown::Plain(held(b));
        }
        self.push(None, Change::Changed { field, a: x, b: y });
    }

    /// Reports `field` when the values differ.
    pub(super) fn field<T: PartialEq + fmt::Debug + ?Sized>(
        &mut self,
        field: &'static str,
        a: &T,
        b: &T,
        show: impl Fn(&T) -> Shown,
    ) {
        self.report(field, a != b, (a, b), show, |v| format!("{v:?}"));
    }

    /// A text field, shown quoted.
    pub(super) fn text(&mut self, field: &'static str, a: &str, b: &str) {
        self.field(field, a, b, |t| Shown::Text(t.to_string()));
    }

    /// A field shown by its `Display`.
    pub(super) fn plain<T: PartialEq + fmt::Debug + fmt::Display>(
        &mut self,
        field: &'static str,
        a: &T,
        b: &T,
    ) {
        self.field(field, a, b, |v| Shown::Plain(v.to_string()));
    }

    /// A part that one side may lack: `step` alone when only one side has it, compared by `f` when both do.
    pub(super) fn option<T>(
        &mut self,
        step: Step,
        a: &Option<T>,
        b: &Option<T>,
        f: impl FnOnce(&mut Cx<'_>, &T, &T),
    ) {
        match (a, b) {
            (Some(x), Some(y)) => self.within(step, |cx| f(cx, x, y)),
            (Some(_), None) => self.push(Some(step), Change::OnlyInA(String::new())),
            (None, Some(_)) => self.push(Some(step), Change::OnlyInB(String::new())),
            (None, None) => {}
        }
    }

    /// Pairs the parts of two lists and compares each pair; reports the parts only one side has and, for
    /// keyed parts, a change of the order of the parts both have.
    pub(super) fn list<T>(&mut self, list: List<T>, a: &[T], b: &[T]) {
        let (ka, kb) = (list.key.of(a), list.key.of(b));
        let in_b: HashMap<&(String, usize), usize> =
            kb.iter().enumerate().map(|(j, k)| (k, j)).collect();
        let label = |(key, n): &(String, usize)| match n {
            1 => key.clone(),
            n => format!("{key} #{n}"),
        };
        let step = |k: &(String, usize)| Step::Item {
            kind: list.kind,
            key: label(k),
        };
        let mut paired = vec![false; b.len()];
        let mut order = Vec::new();
        for (i, k) in ka.iter().enumerate() {
            match in_b.get(k) {
                Some(&j) => {
                    paired[j] = true;
                    order.push(j);
                    self.within(step(k), |cx| (list.compare)(cx, &a[i], &b[j]));
                }
                None => self.push(Some(step(k)), Change::OnlyInA((list.name)(&a[i]))),
            }
        }
        for (j, k) in kb.iter().enumerate() {
            if !paired[j] {
                self.push(Some(step(k)), Change::OnlyInB((list.name)(&b[j])));
            }
        }
        let Key::By { order: field, .. } = list.key else {
            return;
        };
        if order.windows(2).any(|w| w[0] > w[1]) {
            let keys = |js: &[usize]| {
                let shown: Vec<String> = js.iter().map(|&j| label(&kb[j])).collect();
                Shown::Plain(shown.join(", "))
            };
            let a = keys(&order);
            order.sort_unstable();
            let b = keys(&order);
            self.push(None, Change::Changed { field, a, b });
        }
    }
}

impl<T> Key<T> {
    /// The key of each of `items` and its occurrence among equal keys (1 for the first).
    fn of(&self, items: &[T]) -> Vec<(String, usize)> {
        let mut seen: HashMap<String, usize> = HashMap::new();
        items
            .iter()
            .enumerate()
            .map(|(i, item)| match self {
                Key::Position(first) => ((first + i).to_string(), 1),
                Key::By { key, .. } => {
                    let k = key(item);
                    let n = seen.entry(k.clone()).or_default();
                    *n += 1;
                    (k, *n)
                }
            })
            .collect()
    }
}

pub(super) fn hex8(v: &u32) -> Shown {
    Shown::Plain(format!("0x{v:08X}"))
}

pub(super) fn hex4(v: &u16) -> Shown {
    Shown::Plain(format!("0x{v:04X}"))
}

pub(super) fn hex2(v: &u8) -> Shown {
    Shown::Plain(format!("0x{v:02X}"))
}

pub(super) fn or_none<T>(v: &Option<T>, show: impl Fn(&T) -> String) -> String {
    v.as_ref().map_or_else(|| "none".to_string(), show)
}

pub(super) fn joined<T>(items: &[T], show: impl Fn(&T) -> String) -> Shown {
    if items.is_empty() {
        return Shown::Plain("none".into());
    }
    Shown::Plain(items.iter().map(show).collect::<Vec<_>>().join(", "))
}

pub(super) fn bytes_text(bytes: &[u8]) -> String {
    if bytes.is_empty() {
        return "(empty)".into();
    }
    bytes
        .iter()
        .map(|b| format!("{b:02X}"))
        .collect::<Vec<_>>()
        .join(" ")
}
