//! How the process ends when it cannot go on: out of memory, a signal, a file-size limit. Each
//! ends with a message and an exit status instead of an abort with a backtrace, and without
//! leaving a partial temporary file beside an output.
//!
//! The binary installs both at the start of `main` ([`install_exit_handlers`], and
//! [`ReportingAllocator`] as its global allocator); the library functions of the other crates
//! stay free of process-wide state.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::Mutex;

/// The file the command is working on, for the out-of-memory message (read without allocating).
static WORKING_ON: Mutex<String> = Mutex::new(String::new());

/// Records that the command now works on `path` (named if memory runs out).
pub fn working_on(path: &Path) {
    if let Ok(mut current) = WORKING_ON.lock() {
        current.clear();
        current.push_str(&path.display().to_string());
    }
}

/// The system allocator, except that a failed allocation ends the process with
/// "error: not enough memory ..." and exit status 1 (Rust's default prints "memory allocation
/// of N bytes failed", a backtrace, and aborts with status 134).
pub struct ReportingAllocator;

// SAFETY: every method forwards to `System` with the same arguments; only a null result is
// intercepted, and that path never returns.
unsafe impl GlobalAlloc for ReportingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded unchanged.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: forwarded unchanged.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            out_of_memory(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: forwarded unchanged.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            out_of_memory(new_size);
        }
        p
    }
}

/// Writes the message with no allocation (a fixed buffer and the raw `write` call) and exits
/// with status 1 without running destructors or allocating.
fn out_of_memory(size: usize) -> ! {
    let mut buffer = [0u8; 1024];
    let mut len = 0;
    let mut push = |bytes: &[u8]| {
        let n = bytes.len().min(buffer.len() - len);
        buffer[len..len + n].copy_from_slice(&bytes[..n]);
        len += n;
    };
    push(b"error: ");
    if let Ok(file) = WORKING_ON.try_lock()
        && !file.is_empty()
    {
        push(file.as_bytes());
        push(b": ");
    }
    push(b"not enough memory (an allocation of ");
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    let mut n = size;
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    push(&digits[i..]);
    push(b" bytes failed)\n");
    // SAFETY: writing an initialised buffer to stderr, then ending the process.
    unsafe {
        libc::write(2, buffer.as_ptr().cast(), len);
        libc::_exit(1)
    }
}

/// At the start of `main`, before any other thread: SIGINT, SIGTERM and SIGHUP remove the
/// temporary file of a write in progress (`mesh::io::remove_unfinished_writes`) and then end
/// the process by the same signal; a file-size limit (SIGXFSZ) makes the write fail with an
/// error ("File too large") instead of killing the process, so its temporary file is removed
/// too. SIGKILL cannot be caught: the next write into that folder removes what it left.
pub fn install_exit_handlers() {
    #[cfg(unix)]
    // SAFETY: plain libc signal-mask calls on initialised sets, made before any other thread
    // exists (the threads started later inherit the mask, so the signals reach only the
    // waiting thread).
    unsafe {
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for signal in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, signal);
        }
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        let waiter = std::thread::Builder::new()
            .name("signals".into())
            .spawn(move || {
                let mut signal = 0;
                if libc::sigwait(&set, &mut signal) != 0 {
                    return;
                }
                mesh::io::remove_unfinished_writes();
                // End by the signal itself (the shell then reports it as such).
                libc::signal(signal, libc::SIG_DFL);
                libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
                libc::raise(signal);
                libc::_exit(128 + signal);
            });
        if waiter.is_err() {
            libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        }
    }
}
