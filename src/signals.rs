//! The signals that end a progressive render early but keep its work: Ctrl-C (SIGINT) and a
//! scheduler's SIGTERM (Slurm, Kubernetes and systemd send it before they kill). Once the
//! renderer is open, the first of them is recorded and the render stops after the pass in
//! flight, writing the passes done; a second of the same kind ends the process at once (the
//! default action), so a stuck pass never keeps a terminal hostage.

use std::sync::atomic::{AtomicI32, Ordering};

/// The signal received since [`install`] (0: none).
static RECEIVED: AtomicI32 = AtomicI32::new(0);

/// A signal that stopped a render.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stop {
    /// Ctrl-C: a person at the terminal has seen enough.
    Interrupt,
    /// SIGTERM: a scheduler is ending the job (time limit, cancel, preemption).
    Terminate,
}

impl Stop {
    /// The signal's name, as `kill -l` spells it.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Interrupt => "SIGINT",
            Stop::Terminate => "SIGTERM",
        }
    }

    /// The exit status of a render this signal stopped before its planned passes were done:
    /// 0 for Ctrl-C (stopping a progressive render by hand is an ordinary way to end it),
    /// 128 + 15 for SIGTERM, the shell's status of a process ended by it, so that a
    /// scheduler retries the task (a Kubernetes Indexed Job) and `afterok` dependents do not
    /// start on a short slice.
    pub fn exit_status(self) -> u8 {
        match self {
            Stop::Interrupt => 0,
            Stop::Terminate => 128 + 15,
        }
    }
}

#[cfg(unix)]
extern "C" fn on_signal(signal: libc::c_int) {
    // Only an atomic store: async-signal-safe. SIGTERM outranks an earlier Ctrl-C (the
    // scheduler's word decides the exit status); otherwise the first signal is kept.
    if signal == libc::SIGTERM {
        RECEIVED.store(signal, Ordering::SeqCst);
    } else {
        let _ = RECEIVED.compare_exchange(0, signal, Ordering::SeqCst, Ordering::SeqCst);
    }
}

/// Records SIGINT and SIGTERM from now on instead of ending the process (each once: the
/// handler resets to the default action when it runs).
pub fn install() {
    #[cfg(unix)]
    // SAFETY: a plain sigaction with a handler that only stores into an atomic; the struct
    // is zeroed (empty mask) before its fields are set.
    unsafe {
        let mut action: libc::sigaction = std::mem::zeroed();
        action.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
        action.sa_flags = libc::SA_RESTART | libc::SA_RESETHAND;
        libc::sigemptyset(&mut action.sa_mask);
        for signal in [libc::SIGINT, libc::SIGTERM] {
            libc::sigaction(signal, &action, std::ptr::null_mut());
        }
    }
    #[cfg(not(unix))]
    {
        let _ = ctrlc::set_handler(|| {
            let _ = RECEIVED.compare_exchange(0, 2, Ordering::SeqCst, Ordering::SeqCst);
        });
    }
}

/// The signal received since [`install`], if any.
pub fn received() -> Option<Stop> {
    match RECEIVED.load(Ordering::SeqCst) {
        0 => None,
        #[cfg(unix)]
        libc::SIGTERM => Some(Stop::Terminate),
        _ => Some(Stop::Interrupt),
    }
}
