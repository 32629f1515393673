//! Action latency (`[latency] action = N`, `envspec::noise`): the env applies the action given
//! `N` steps earlier; zeros until `N` actions have been given since the reset. Everything
//! downstream (ctrl, and reward terms or info reading `action`) sees the applied action. A ring
//! of `N` actions, sized when the env is built: stepping allocates nothing.

pub(crate) struct ActionLatency {
    nu: usize,
    steps: usize,
    /// The slot holding the oldest action (the one applied next).
    head: usize,
    buf: Vec<f64>,
}

impl ActionLatency {
    /// None without latency (nothing changes on the step path).
    pub(crate) fn new(steps: usize, nu: usize) -> Option<ActionLatency> {
        (steps > 0).then(|| ActionLatency {
            nu,
            steps,
            head: 0,
            buf: vec![0.0; steps * nu],
        })
    }

    /// The ring's size in bytes (part of an env's memory, for the vector-env check).
    pub(crate) fn bytes(&self) -> u64 {
        (self.buf.len() * std::mem::size_of::<f64>()) as u64
    }

    /// At reset: no action given yet.
    pub(crate) fn clear(&mut self) {
        self.buf.fill(0.0);
        self.head = 0;
    }

    /// Replace the given `action` with the one given `steps` steps ago, and keep the given one.
    pub(crate) fn apply(&mut self, action: &mut [f64]) {
        let slot = &mut self.buf[self.head * self.nu..(self.head + 1) * self.nu];
        action.swap_with_slice(slot);
        self.head = (self.head + 1) % self.steps;
    }
}
