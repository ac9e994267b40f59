//! A request to stop a long computation: a time run, a static solve, a
//! steady state, polled between their steps.
//!
//! The long calls of the library take an [`Interrupt`] in their
//! `…_interruptible` forms (the plain forms pass [`Interrupt::NEVER`]): a
//! time run polls it after every step, the static solver at every Newton
//! iteration, a Campbell diagram at every speed. When the check says so,
//! the call returns [`crate::Error::Interrupted`] at once, its inputs left
//! as they were. Polling [`Interrupt::NEVER`] is one branch; a check is the
//! caller's function, called from the computing thread, that should be
//! cheap (it is called at every step): the Python package's looks at a
//! clock and takes Python's lock to run its signal handlers only every
//! 50 ms.

use crate::{Error, Result};

/// The check of a long computation for a request to stop (see the
/// module's documentation). `Copy`: handed down by value.
#[derive(Clone, Copy, Default)]
pub struct Interrupt<'a> {
    check: Option<&'a (dyn Fn() -> bool + Sync)>,
}

impl Interrupt<'static> {
    /// Never stops: what the plain forms of the long calls pass.
    pub const NEVER: Interrupt<'static> = Interrupt { check: None };
}

impl<'a> Interrupt<'a> {
    /// Stop when `check()` returns `true` (called at every step; keep it cheap).
    pub fn new(check: &'a (dyn Fn() -> bool + Sync)) -> Self {
        Interrupt { check: Some(check) }
    }

    /// Whether the computation should stop now.
    #[inline]
    pub fn requested(&self) -> bool {
        match self.check {
            Some(f) => f(),
            None => false,
        }
    }

    /// [`Error::Interrupted`] if the computation should stop now.
    #[inline]
    pub fn check(&self) -> Result<()> {
        if self.requested() {
            Err(Error::Interrupted)
        } else {
            Ok(())
        }
    }
}

impl std::fmt::Debug for Interrupt<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(if self.check.is_some() {
            "Interrupt(check)"
        } else {
            "Interrupt::NEVER"
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn never_does_not_stop_and_a_check_is_called_each_time() {
        assert!(Interrupt::NEVER.check().is_ok());
        let calls = AtomicUsize::new(0);
        let stop_at_third = || calls.fetch_add(1, Ordering::Relaxed) == 2;
        let i = Interrupt::new(&stop_at_third);
        assert!(i.check().is_ok() && i.check().is_ok());
        assert_eq!(i.check(), Err(Error::Interrupted));
        assert_eq!(calls.load(Ordering::Relaxed), 3);
    }
}
