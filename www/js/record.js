// Recording the view: *Record* films the canvas with the simulated time written on it
// (MediaRecorder, WebM; *Stop* downloads the video), *Snapshot* saves a PNG of it; both named
// after the scene and the simulated time. Each frame drawn on the view is copied, in the same
// task (while a WebGL drawing buffer still holds it), onto a 2D canvas of the same size with
// the caption; the video is that canvas' stream. The naming, the caption and the choice of
// format are pure (tested under `node --test`).

import { download, fileStem } from './files.js';
import { toast } from './hud.js';

/// The formats tried, best first: all WebM.
export const VIDEO_TYPES = ['video/webm;codecs=vp9', 'video/webm;codecs=vp8', 'video/webm'];

/// The first of VIDEO_TYPES that `supported(type)` accepts, or ''.
export function videoType(supported) {
  return VIDEO_TYPES.find((t) => supported(t)) ?? '';
}

/// The caption drawn on recordings and snapshots: the scene and its simulated time.
export function captionText(name, t) {
  return `${name || 'scene'} · t = ${(Number.isFinite(t) ? t : 0).toFixed(3)} s`;
}

/// Frames a second of the video (the view draws at most about this many while stepping).
const FPS = 30;

export class Recorder {
  /// Records `canvas` (the view).
  constructor(canvas) {
    this.canvas = canvas;
    this.copy = document.createElement('canvas');
    this.ctx = this.copy.getContext('2d');
    this.media = null; // the MediaRecorder while recording
    this.waiting = []; // snapshots waiting for the next frame drawn
    this.started = 0; // simulated time at the start of the recording
  }

  get recording() {
    return !!this.media;
  }

  /// Called after each frame drawn on the view, with a function giving the caption: copies
  /// the frame if a recording or a snapshot wants it.
  drawn(caption) {
    if (!this.media && !this.waiting.length) return;
    this.compose(caption(), !this.media);
    for (const w of this.waiting.splice(0)) this.copy.toBlob((b) => (b ? w.resolve(b) : w.reject(new Error('no PNG'))), 'image/png');
  }

  /// Copies the view with `caption` at its bottom left; `resize`: to the view's current size
  /// (not while a video is recorded: its size is fixed).
  compose(caption, resize) {
    const src = this.canvas, c = this.copy, ctx = this.ctx;
    if (resize && (c.width !== src.width || c.height !== src.height)) {
      c.width = src.width;
      c.height = src.height;
    }
    ctx.fillStyle = '#edf2fa';
    ctx.fillRect(0, 0, c.width, c.height);
    ctx.drawImage(src, 0, 0, c.width, c.height);
    const scale = c.width / Math.max(1, src.clientWidth || c.width);
    const size = Math.round(15 * scale), pad = Math.round(8 * scale);
    ctx.font = `600 ${size}px system-ui, -apple-system, "Segoe UI", Roboto, sans-serif`;
    const w = ctx.measureText(caption).width;
    ctx.fillStyle = 'rgba(255, 255, 255, 0.85)';
    ctx.fillRect(pad, c.height - 2 * pad - size - pad, w + 2 * pad, size + 2 * pad);
    ctx.fillStyle = '#1d2433';
    ctx.textBaseline = 'middle';
    ctx.fillText(caption, 2 * pad, c.height - 2 * pad - size / 2);
  }

  /// A PNG of the next frame drawn (the caller makes one be drawn).
  snapshot() {
    return new Promise((resolve, reject) => this.waiting.push({ resolve, reject }));
  }

  /// Starts recording at simulated time `t`, with the current frame as the first (`caption`).
  start(t, caption) {
    const type = typeof MediaRecorder === 'undefined' ? '' : videoType((x) => MediaRecorder.isTypeSupported(x));
    if (!type || !this.copy.captureStream) throw new Error('this browser cannot record WebM video');
    this.compose(caption, true);
    this.stream = this.copy.captureStream(FPS);
    this.chunks = [];
    this.media = new MediaRecorder(this.stream, { mimeType: type, videoBitsPerSecond: 6e6 });
    this.media.ondataavailable = (e) => { if (e.data.size) this.chunks.push(e.data); };
    this.media.start(500);
    this.started = t;
  }

  /// Stops recording; resolves to the video (a WebM blob).
  stop() {
    const media = this.media;
    this.media = null;
    return new Promise((resolve, reject) => {
      media.onstop = () => {
        for (const track of this.stream.getTracks()) track.stop();
        resolve(new Blob(this.chunks, { type: 'video/webm' }));
      };
      media.onerror = (e) => reject(e.error ?? new Error('the recording failed'));
      media.stop();
    });
  }
}

/// Wires the Record and Snapshot buttons to `app.recorder`.
export function setupRecording(app) {
  const rec = app.recorder;
  const record = document.getElementById('record');
  const name = () => app.session.scene.name;
  const caption = () => captionText(name(), app.simTime);
  record.addEventListener('click', async () => {
    if (!rec.recording) {
      try {
        rec.start(app.simTime, caption());
      } catch (e) {
        toast(`Cannot record: ${e.message}`);
        return;
      }
      record.textContent = 'Stop';
      record.classList.add('recording');
      record.setAttribute('aria-pressed', 'true');
      app.redraw();
      return;
    }
    const t0 = rec.started;
    record.textContent = 'Record';
    record.classList.remove('recording');
    record.setAttribute('aria-pressed', 'false');
    const video = await rec.stop();
    const file = `${fileStem(name(), t0, app.simTime)}.webm`;
    download(video, file);
    toast(`Saved ${file} (${(video.size / 1e6).toPrecision(2)} MB)`);
  });
  document.getElementById('snapshot').addEventListener('click', async () => {
    const png = rec.snapshot();
    app.redraw();
    const blob = await png;
    download(blob, `${fileStem(name(), app.simTime)}.png`);
  });
}
