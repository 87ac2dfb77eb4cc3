// An X display for Firefox's WebGL2: Firefox makes WebGL contexts with EGL on an X display, so
// even headless it needs an X server (without one it offers no WebGL at all). Xvfb with Mesa's
// software rasteriser (llvmpipe, Debian's libgl1-mesa-dri) is enough.
import { spawn } from 'node:child_process';

/// Starts `Xvfb` (XVFB, default on PATH) on a free display; resolves to { display, stop() }.
/// Without Xvfb, falls back to an existing DISPLAY (a desktop session) when there is one.
export function startXvfb({ width = 1600, height = 1000 } = {}) {
  const bin = process.env.XVFB || 'Xvfb';
  return new Promise((resolve, reject) => {
    // -displayfd: Xvfb picks a free display number and writes it to fd 3 once it is ready.
    const proc = spawn(bin, ['-displayfd', '3', '-screen', '0', `${width}x${height}x24`, '-nolisten', 'tcp'], {
      stdio: ['ignore', 'ignore', 'pipe', 'pipe'],
    });
    let stderr = '', fd3 = '', done = false;
    proc.stderr.on('data', (d) => { stderr += d; });
    proc.stdio[3].on('data', (d) => {
      fd3 += d;
      if (done || !fd3.includes('\n')) return;
      done = true;
      resolve({ display: `:${fd3.trim()}`, stop: () => proc.kill() });
    });
    proc.on('error', (e) => {
      if (done) return;
      done = true;
      if (e.code === 'ENOENT' && process.env.DISPLAY) {
        resolve({ display: process.env.DISPLAY, stop: () => {} });
      } else {
        reject(new Error(`cannot start ${bin} (${e.message}): install Debian's xvfb package, or set XVFB`));
      }
    });
    proc.on('exit', (code, signal) => {
      if (done) return;
      done = true;
      reject(new Error(`${bin} exited (${signal || `status ${code}`}) before it opened a display: ${stderr.trim()}`));
    });
  });
}
