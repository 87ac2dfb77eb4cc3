// The soil lab on the page, in headless Chromium (Debian's package through playwright-core):
// the Lab button opens it; a shear-box run with a lid of 10 kPa plots τ–δ and the lid's rise
// from the solver's readings, the sample holds the lid with the slider's load within 2 %
// (statics), and it adds a failure point (τ and σ_n on the shear plane over the last quarter
// of the travel); a second run at 20 kPa reads a larger τ at a larger σ_n, and the page fits
// the envelope of the two (the read-back φ and c are `fitEnvelope` of the recorded failures)
// and says why the shear box and the biaxial test read different angles, quoting Davis's
// 26.6° for φ = 30°, ψ = 0; with a third run at 40 kPa the fitted angle lies within 2° of
// Davis's; a biaxial run plots q–ε_a and ε_v–ε_a and adds a failure circle. The soil-lab
// lessons open in the Lab from their links, ask before they run (nothing judged, no choice
// marked), show no judgement before their last run has ended, and then answer with the
// quantity the solver's reader reports (the lid's last rise: it rises with ψ = 10°; the ratio
// of the two shear strengths: τ about doubles with the load) or, for the two-tests lesson,
// with the difference of the envelopes the page fitted to its two shear boxes and two biaxial
// tests (the shear box reads lower, and the verdict says why with Davis's formula and the
// measured angles). Served by `cargo xtask test` (MPM_URL).
//
//   MPM_URL=http://127.0.0.1:8080/ node --test www/tests/lab.test.mjs
import { test, before, after } from 'node:test';
import assert from 'node:assert/strict';
import { mkdirSync } from 'node:fs';
import { join } from 'node:path';
import { launch, openPage } from './browser.mjs';

const URL_ROOT = process.env.MPM_URL || 'http://127.0.0.1:8080/';
const OUT = process.env.MPM_OUT || 'target/e2e';
mkdirSync(OUT, { recursive: true });

let browser;
before(async () => { browser = await launch(); });
after(async () => { await browser?.close(); });

/// Sets the lab's sliders and runs one test to its end; returns the lab's state after it.
const runTest = async (page, test, load) => {
  await page.selectOption('#lab-test', test);
  await page.evaluate((v) => { const e = document.getElementById('lab-load'); e.value = v; e.dispatchEvent(new Event('input')); }, String(load));
  const before = await page.evaluate(() => mpmLab.runs.length);
  await page.click('#lab-run');
  await page.waitForFunction((n) => mpmLab.runs.length > n && !mpmLab.running, before, { timeout: 300_000 });
  return page.evaluate(() => ({
    runs: mpmLab.runs, readings: mpmLab.readings, fits: mpmLab.fits, speed: mpmLab.speed,
    fit: document.getElementById('lab-fit').textContent, why: document.getElementById('lab-why').textContent,
    status: document.getElementById('lab-status').textContent,
  }));
};

test('the lab runs two shear boxes, fits their envelope and says why the tests differ', { timeout: 900_000 }, async () => {
  const { page, errors } = await openPage(browser.context, URL_ROOT);
  assert.equal(await page.isVisible('#lab'), false);
  await page.click('#lab-open');
  assert.equal(await page.isVisible('#lab'), true);

  const first = await runTest(page, 'shear_box', 10);
  console.log(`shear box at 10 kPa: ${first.status}`);
  assert.ok(first.readings.length >= 45, `${first.readings.length} readings (0.1 s, one every 2 ms)`);
  const held = first.readings.filter((r) => r.time > 0.02).map((r) => r.lid_support);
  const support = held.reduce((a, b) => a + b, 0) / held.length;
  assert.ok(Math.abs(support / 10e3 - 1) < 0.02, `the sample holds the lid with ${support} Pa against the slider's 10 kPa`);
  assert.ok(first.readings.some((r) => r.shear_stress > 0), 'the sample resists the shear');
  assert.equal(first.runs.length, 1);
  assert.equal(first.fits.shear_box, null, 'one run fixes no envelope');

  const second = await runTest(page, 'shear_box', 20);
  console.log(`shear box at 20 kPa: ${second.status}`);
  const [[sn1, t1], [sn2, t2]] = second.runs.map((r) => r.failure);
  assert.ok(sn2 > sn1 && t2 > t1, `τ ${t1} Pa at ${sn1} Pa, ${t2} Pa at ${sn2} Pa`);
  const fit = second.fits.shear_box;
  assert.ok(fit, 'two runs fit an envelope');
  const slope = (t2 - t1) / (sn2 - sn1);
  assert.ok(Math.abs(fit.friction_angle - (Math.atan(slope) * 180) / Math.PI) < 0.05,
    `read-back ${fit.friction_angle}° against the two points' slope`);
  assert.ok(second.fit.includes(`φ read ${fit.friction_angle.toFixed(1)}°`), second.fit);
  assert.ok(second.why.includes('Davis (1968)') && second.why.includes('26.6°'), second.why);
  // both figures stated, never that they agree
  assert.ok(second.why.includes(`The shear box read ${fit.friction_angle.toFixed(1)}°; Davis's closed form gives 26.6°`), second.why);
  assert.doesNotMatch(second.why, /agrees|matches/, second.why);
  await page.screenshot({ path: join(OUT, 'lab-shear-box.png') });

  // a third load: the envelope of the three points, as the page shows it beside Davis's
  const third = await runTest(page, 'shear_box', 40);
  const fit3 = third.fits.shear_box;
  const points = third.runs.filter((r) => r.test === 'shear_box').map((r) => r.failure);
  assert.equal(points.length, 3);
  const again = await page.evaluate((p) => import('./www/pkg/mpm.js').then((m) => JSON.parse(m.fitEnvelope('points', new Float64Array(p.flat())))), points);
  assert.deepEqual(fit3, again, 'the read-back is the fit of the three failures');
  assert.ok(Math.abs(fit3.friction_angle - 26.57) < 2, `three runs read ${fit3.friction_angle}° against Davis's 26.57°`);
  console.log(`shear box at 10/20/40 kPa: failures ${points.map(([s, t]) => `${(t / 1e3).toFixed(2)} kPa at ${(s / 1e3).toFixed(2)}`).join(', ')}; ${third.fit} ${third.why}`);

  const biaxial = await runTest(page, 'biaxial', 20);
  console.log(`biaxial at 20 kPa: ${biaxial.status}`);
  assert.ok(biaxial.readings.length > 100);
  assert.ok(biaxial.readings.at(-1).axial_strain > 0, 'the platen compresses the sample');
  const [s1, s3] = biaxial.runs.at(-1).failure;
  assert.ok(Math.abs(s3 / 20e3 - 1) < 1e-9 && s1 > s3, `circle σ1 ${s1}, σ3 ${s3}`);
  await page.screenshot({ path: join(OUT, 'lab-biaxial.png') });
  assert.deepEqual(errors, []);
  await page.close();
});

/// Opens soil-lab lesson `id` from its link; checks it waits unjudged, picks `choice`, runs it
/// and returns the lab's state once answered. Whenever the page shows a judgement (the verdict's
/// "Measured", a choice marked, or the lesson's answer set; watched on every change and every
/// frame) it records how many runs had ended and whether one was running: the first must come
/// after the last of the lesson's `runs` runs ended.
const lesson = async (id, choice, runs, more = async () => ({})) => {
  const { page, errors } = await openPage(browser.context, `${URL_ROOT}#lesson=${id}`);
  await page.waitForFunction((id) => mpmLab.lessonRun?.id === id, id, { timeout: 60_000 });
  assert.equal(await page.isVisible('#lab'), true, `${id}: the lesson opens the Lab`);
  assert.equal(await page.isVisible('#lab-lesson-question [data-choice="0"]'), true);
  const unjudged = await page.evaluate(() => ({
    answer: mpmLab.lessonRun.answer, runs: mpmLab.runs.length,
    marked: document.querySelectorAll('#lab-lesson-question .answer').length,
    verdict: document.getElementById('lab-lesson-verdict').textContent,
  }));
  assert.deepEqual(unjudged, { answer: null, runs: 0, marked: 0, verdict: 'Predict first: pick an answer, then press Run.' }, id);
  await page.click(`#lab-lesson-question [data-choice="${choice}"]`);
  await page.evaluate(() => {
    window.judged = [];
    const box = document.getElementById('lab-lesson-question');
    const seen = () => {
      const shown = /Measured/.test(document.getElementById('lab-lesson-verdict').textContent)
        || box.querySelector('.answer') !== null || mpmLab.lessonRun?.answer != null;
      if (shown && !judged.length) judged.push({ runs: mpmLab.runs.length, running: mpmLab.running });
    };
    new MutationObserver(seen).observe(box, { subtree: true, childList: true, characterData: true, attributes: true });
    const frame = () => { seen(); if (!judged.length) requestAnimationFrame(frame); };
    requestAnimationFrame(frame);
  });
  await page.click('#lab-run');
  await page.waitForFunction(() => mpmLab.lessonRun.answer !== null, null, { timeout: 600_000 });
  const s = await page.evaluate(() => ({
    answer: mpmLab.lessonRun.answer, values: mpmLab.lessonRun.values, runs: mpmLab.runs, fits: mpmLab.fits,
    last: mpmLab.readings.at(-1), psi: document.getElementById('lab-psi').value, verdict: document.getElementById('lab-lesson-verdict').textContent,
    marked: [...document.querySelectorAll('#lab-lesson-question .answer')].map((b) => b.dataset.choice),
    why: document.getElementById('lab-why').textContent, judged: window.judged,
  }));
  console.log(`${id}: ${s.verdict}`);
  assert.equal(s.runs.length, runs, `${id}: every run ended`);
  assert.deepEqual(s.judged, [{ runs, running: false }], `${id}: judged only once its ${runs} runs had ended`);
  assert.deepEqual(s.marked, [String(s.answer.index)], `${id}: the measured choice is marked`);
  await page.screenshot({ path: join(OUT, `lab-lesson-${id}.png`) });
  Object.assign(s, await more(page, s));
  assert.deepEqual(errors, []);
  await page.close();
  return s;
};

test('the dilatancy lesson answers with the lid rise its run read', { timeout: 900_000 }, async () => {
  const s = await lesson('dilatancy', 2, 1);
  assert.equal(s.runs.length, 1);
  assert.equal(s.psi, '10', 'the Lab shows the lesson\'s ψ');
  // the solver's reader: the lid's rise at the run's last reading
  assert.equal(s.answer.value, s.last.lid_rise);
  assert.equal(s.answer.index, 2, `ψ = 10°: the lid rises (${s.answer.value} m)`);
  assert.match(s.verdict, /the lid rose .* mm → “It rises by more than 0.05 mm”\. Your prediction was right\./);
});

test('the shear-box lesson answers with the ratio of its two runs\' shear strengths', { timeout: 900_000 }, async () => {
  const s = await lesson('shear_box', 1, 2);
  assert.equal(s.runs.length, 2);
  const [[sn1, t1], [sn2, t2]] = s.runs.map((r) => r.failure);
  assert.ok(sn2 > sn1 && t2 > t1, `τ ${t1} Pa at σ_n ${sn1} Pa, ${t2} Pa at ${sn2} Pa`);
  // each run's shear strength as its reader reports it, the second over the first
  assert.deepEqual(s.values, [t1, t2]);
  assert.ok(Math.abs(s.answer.value - t2 / t1) < 1e-12, `${s.answer.value} against ${t2 / t1}`);
  assert.equal(s.answer.index, 1, `twice the load: τ about doubles (${s.verdict})`);
  assert.match(s.verdict, /Your prediction was right\./);
});

test('the two-tests lesson judges from the envelopes the page fitted to both tests', { timeout: 900_000 }, async () => {
  // the envelopes of the runs' failures, fitted again by the solver's fitEnvelope
  const s = await lesson('two_tests', 0, 4, async (page, { runs }) => ({
    refit: await page.evaluate((runs) => import('./www/pkg/mpm.js').then((m) => {
      const fit = (kind, test) => JSON.parse(m.fitEnvelope(kind, new Float64Array(runs.filter((r) => r.test === test).flatMap((r) => r.failure))));
      return { shear_box: fit('points', 'shear_box'), biaxial: fit('circles', 'biaxial') };
    }), runs),
  }));
  // two shear boxes, then two biaxial tests, at the lesson's loads
  assert.deepEqual(s.runs.map((r) => r.test), ['shear_box', 'shear_box', 'biaxial', 'biaxial']);
  assert.deepEqual(s.runs.slice(2).map((r) => r.failure[1]), [10e3, 40e3], 'σ3 of the biaxial runs');
  // the answer is the difference of the two envelopes fitted to the runs' failures
  const { refit } = s;
  assert.deepEqual(s.fits, refit, 'the page\'s envelopes are those of its four runs');
  const [sb, bx] = [refit.shear_box.friction_angle, refit.biaxial.friction_angle];
  assert.equal(s.answer.value, sb - bx);
  // each angle within the bands of tests/lab.rs: Davis's 26.57° and φ = 30°, within 2°
  assert.ok(Math.abs(sb - 26.57) < 2 && Math.abs(bx - 30) < 2, `shear box ${sb}°, biaxial ${bx}°`);
  assert.equal(s.answer.index, 0, `Davis: the shear box reads lower (${s.verdict})`);
  assert.ok(s.verdict.startsWith(`Measured by the page: the shear box's envelope ${(bx - sb).toFixed(1)}° lower than the biaxial test's → “The shear box reads lower (by 1° or more)”. Your prediction was right.`), s.verdict);
  // the why: Davis's formula and figure, with the two angles the page measured
  for (const part of ['tan φ_ds = sin φ cos ψ / (1 − sin φ sin ψ)', '26.6° for φ = 30°, ψ = 0°', `The shear box read ${sb.toFixed(1)}°`, `the biaxial test reads ${bx.toFixed(1)}°`, 'φ = 30°']) {
    assert.ok(s.verdict.includes(part), `the verdict says “${part}”: ${s.verdict}`);
  }
  assert.equal(s.why, '', 'said once, in the verdict');
});
