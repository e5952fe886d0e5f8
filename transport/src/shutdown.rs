//! Graceful shutdown on Ctrl-C or SIGTERM (what `docker stop` and systemd send), for the server
//! and the agents alike.

use std::sync::atomic::{AtomicBool, Ordering};

use tokio::sync::watch;

/// Set once a signal has arrived, for code that waits outside the async runtime (a thread blocked on a live
/// source) and cannot await [`Shutdown::requested`].
static SIGNALLED: AtomicBool = AtomicBool::new(false);

/// True once Ctrl-C or SIGTERM has arrived (see [`Shutdown::listen`]).
pub fn signalled() -> bool {
    SIGNALLED.load(Ordering::Relaxed)
}

/// A handle on the process-wide "please stop" flag; cheap to clone.
#[derive(Debug, Clone)]
pub struct Shutdown {
    requested: watch::Receiver<bool>,
}

impl Shutdown {
    /// Starts listening for Ctrl-C and SIGTERM (needs a running Tokio runtime).
    pub fn listen() -> Self {
        let (sender, requested) = watch::channel(false);
        tokio::spawn(async move {
            wait_for_signal().await;
            tracing::info!("shutdown requested");
            SIGNALLED.store(true, Ordering::Relaxed);
            // Nobody listening any more just means the run already ended.
            let _ = sender.send(true);
        });
        Self { requested }
    }

    /// True once a signal has arrived.
    pub fn is_requested(&self) -> bool {
        *self.requested.borrow()
    }

    /// Resolves when a signal arrives (never, if none does).
    pub async fn requested(&mut self) {
        if self.requested.wait_for(|stop| *stop).await.is_err() {
            // The listener task is gone without a signal: nothing will ever ask us to stop.
            std::future::pending::<()>().await;
        }
    }
}

/// Completes on Ctrl-C or, on Unix, SIGTERM. When a signal cannot be listened for, says so and
/// waits for the other.
pub async fn wait_for_signal() {
    let ctrl_c = async {
        if let Err(e) = tokio::signal::ctrl_c().await {
            tracing::warn!(error = %e, "cannot listen for Ctrl-C");
            std::future::pending::<()>().await;
        }
    };
    #[cfg(unix)]
    {
        use tokio::signal::unix::{signal, SignalKind};
        match signal(SignalKind::terminate()) {
            Ok(mut term) => {
                tokio::select! {
                    _ = ctrl_c => {}
                    _ = term.recv() => {}
                }
            }
            Err(e) => {
                tracing::warn!(error = %e, "cannot listen for SIGTERM");
                ctrl_c.await;
            }
        }
    }
    #[cfg(not(unix))]
    ctrl_c.await;
}
