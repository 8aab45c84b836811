//! Warnings as values. Library code that notices something the caller should know, but that
//! is no error (a glTF primitive skipped, the GPU giving way to the CPU), calls [`warn`]. Inside
//! [`collect`] the warning is kept and returned to the caller; outside it (older callers of the
//! inner modules) it goes to stderr as `warning: MESSAGE`, as before.

use std::cell::RefCell;
use std::fmt;

/// Something the caller should know about a load or a render that did not stop it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// What happened, naming the file (and field) where there is one.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message)
    }
}

thread_local! {
    /// The warnings of the innermost [`collect`] running on this thread (none: print them).
    static SINK: RefCell<Option<Vec<Warning>>> = const { RefCell::new(None) };
}

/// Reports `message`: kept by the enclosing [`collect`], else printed to stderr.
pub fn warn(message: impl Into<String>) {
    // The values it echoes of a scene file, escaped as errors' are (`crate::escape`).
    let message = crate::escape::escape(&message.into()).into_owned();
    let unheard = SINK.with(|sink| match sink.borrow_mut().as_mut() {
        Some(list) => {
            list.push(Warning { message });
            None
        }
        None => Some(message),
    });
    if let Some(message) = unheard {
        eprintln!("warning: {message}");
    }
}

/// Runs `f`, returning what it returned and the warnings it reported on this thread.
pub fn collect<T>(f: impl FnOnce() -> T) -> (T, Vec<Warning>) {
    let outer = SINK.with(|sink| sink.borrow_mut().replace(Vec::new()));
    let value = f();
    let warnings = SINK.with(|sink| std::mem::replace(&mut *sink.borrow_mut(), outer));
    (value, warnings.unwrap_or_default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn collect_keeps_warnings_in_order_and_nests() {
        let ((inner, ()), outer) = collect(|| {
            warn("a");
            let inner = collect(|| warn("b"));
            warn("c");
            (inner.1, ())
        });
        let texts = |w: &[Warning]| w.iter().map(|w| w.message.clone()).collect::<Vec<_>>();
        assert_eq!(texts(&inner), ["b"]);
        assert_eq!(texts(&outer), ["a", "c"]);
    }
}
