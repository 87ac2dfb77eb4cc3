// The Web Worker that holds the simulation (sim-host.js): one worker, one single-threaded
// solver. It steps in slices of at most SLICE_MS, so that a command waits at most a slice and a
// step; between slices it answers the page's messages. While the simulation is behind real time
// it steps again at once; while it is ahead (or paused) it waits for the next display frame.

import { SimHost, SLICE_MS } from './sim-host.js';

const FRAME_MS = 1000 / 60;
const queue = [];
let host = null;
self.onmessage = (e) => (host ? host.handle(e.data) : queue.push(e.data));

// A zero-delay yield that lets waiting messages in first (setTimeout(0) is clamped to 4 ms).
const channel = new MessageChannel();
channel.port1.onmessage = tick;

function tick() {
  const start = performance.now();
  const behind = host.slice(SLICE_MS);
  host.flush();
  if (behind) channel.port2.postMessage(0);
  else setTimeout(tick, Math.max(0, FRAME_MS - (performance.now() - start)));
}

SimHost.create((message, transfer) => self.postMessage(message, transfer), true).then(
  (h) => {
    host = h;
    for (const m of queue.splice(0)) host.handle(m);
    tick();
  },
  (e) => self.postMessage({ type: 'failed', error: e.message }),
);
