// The frame rate while dragging: a long gizmo drag in inverse mode on the
// demo character, sampling the app's own counters (frames rendered, poses
// applied from /api/drag answers), plain and with the motion trail of the
// dragged control and the ghosts on (each drag answer re-reads both).
// Written to test-results/frame-rate.json and frame-rate-overlays.json.
// The figures are measured, not asserted: each gesture lasts at least 3 s
// and until the state the test checks is reached (answers, poses, frames
// played), so a loaded machine makes it longer, never failing.

import { mkdirSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { clickControl, expect, expectSelection, setMode, test, webDir } from './fixtures';

for (const overlays of [false, true])
test(`frame rate while dragging${overlays ? ' with a motion trail and ghosts' : ''}`, async ({ app: page, server, shots }, testInfo) => {
  await setMode(page, server, 'inverse');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  if (overlays) {
    await page.keyboard.press('t');
    await page.keyboard.press('o');
    await expect.poll(() => page.evaluate(() => (window as any).rigel.overlays.state().ghosts.length)).toBe(6);
    await expect.poll(() => page.evaluate(() => (window as any).rigel.overlays.state().trails.length)).toBe(1);
  }
  await expect.poll(() => page.evaluate(() => (window as any).rigel.gizmoHandle('y') !== null)).toBe(true);

  const hnd = await page.evaluate(() => (window as any).rigel.gizmoHandle('y'));
  const start = await page.evaluate(() => (window as any).rigel.stats());
  await page.mouse.move(hnd.x, hnd.y);
  await page.mouse.down();
  const t0 = Date.now();
  const samples: number[] = [];
  const durationMs = 3000;
  let i = 0;
  // At least 3 s, and until the server has answered 5 moves (a loaded machine answers fewer per second).
  const answered = async (): Promise<number> => (await page.evaluate(() => (window as any).rigel.stats())).drag.answers - start.drag.answers;
  for (;;) {
    if (Date.now() - t0 >= durationMs && (await answered()) >= 5) break;
    // Up and down the arrow, 60 px each way.
    const phase = (i++ % 60) / 60;
    const off = 60 * Math.sin(phase * 2 * Math.PI);
    await page.mouse.move(hnd.x + hnd.dx * off, hnd.y + hnd.dy * off);
    if (i % 10 === 0) samples.push((await page.evaluate(() => (window as any).rigel.stats())).fps);
  }
  const elapsed = (Date.now() - t0) / 1000;
  const end = await page.evaluate(() => (window as any).rigel.stats());
  await shots.take(overlays ? 'while-dragging-with-overlays' : 'while-dragging');
  await page.mouse.up();
  await expect.poll(() => page.evaluate(() => (window as any).rigel.app.drag.active)).toBe(false);

  const result = {
    browser: `headless ${testInfo.project.use.browserName ?? 'chromium'}`,
    renderer: end.renderer,
    antialias: end.antialias,
    mode: 'inverse',
    trailAndGhosts: overlays,
    control: 'hand.L_ctrl',
    seconds: Number(elapsed.toFixed(2)),
    mouseMoves: i,
    framesRendered: end.frames - start.frames,
    renderedFps: Number(((end.frames - start.frames) / elapsed).toFixed(1)),
    posesApplied: end.poses - start.poses,
    posesPerSecond: Number(((end.poses - start.poses) / elapsed).toFixed(1)),
    dragRequests: end.drag.requests - start.drag.requests,
    dragAnswers: end.drag.answers - start.drag.answers,
    dragFailures: end.drag.failures - start.drag.failures,
    meanDragRoundTripMs: Number(end.drag.meanRoundTripMs.toFixed(2)),
    drawCalls: end.drawCalls,
    controlSegments: end.controlSegments,
    fpsSamples: samples,
  };
  const file = overlays ? 'frame-rate-overlays.json' : 'frame-rate.json';
  console.log(`frame rate while dragging${overlays ? ' (trail and ghosts on)' : ''}: ${JSON.stringify(result)}`);
  await testInfo.attach(file, { body: JSON.stringify(result, null, 2), contentType: 'application/json' });
  mkdirSync(join(webDir, 'test-results'), { recursive: true });
  writeFileSync(join(webDir, 'test-results', file), JSON.stringify(result, null, 2) + '\n');

  expect(result.dragFailures).toBe(0);
  // The drag path keeps answering and the viewport draws what it answers
  // (the rates are figures to read, not thresholds: a shared CPU's).
  expect(result.dragAnswers).toBeGreaterThanOrEqual(5);
  await expect.poll(async () => (await page.evaluate(() => (window as any).rigel.stats())).poses - start.poses).toBeGreaterThanOrEqual(5);
  expect(result.framesRendered).toBeGreaterThan(0);
});

// The frame rate while playing: two keys on the hand 24 frames apart, played
// for 3 s (the timeline steps one frame per POST /api/time and fetches the
// pose), plain and with the trail and ghosts on (both re-read each frame).
for (const overlays of [false, true])
test(`frame rate while playing${overlays ? ' with a motion trail and ghosts' : ''}`, async ({ app: page, server }, testInfo) => {
  await setMode(page, server, 'forward');
  await clickControl(page, 'hand.L_ctrl');
  await expectSelection(page, server, ['hand.L_ctrl']);
  const hand = (await server.uuids()).get('hand.L_ctrl')!;
  for (const [f, v] of [[0, 0], [24, 0.2]] as const) {
    expect((await server.post('/api/time', { frame: f })).status).toBe(200);
    expect((await server.post('/api/channel-values', { controls: [hand], attrs: ['translateY'], value: v })).status).toBe(200);
    expect((await server.post('/api/key', { controls: [hand] })).status).toBe(200);
  }
  await expect.poll(() => page.evaluate(() => (window as any).rigel.store.keys?.frames.length)).toBe(2);
  if (overlays) {
    await page.keyboard.press('t');
    await page.keyboard.press('o');
    await expect.poll(() => page.evaluate(() => (window as any).rigel.overlays.state().trails.length)).toBe(1);
  }
  const start = await page.evaluate(() => (window as any).rigel.stats());
  const played0 = await page.evaluate(() => (window as any).rigel.timeline.playedFrames.length);
  await page.keyboard.press('Space');
  await expect(page.getByTestId('play')).toHaveClass(/active/);
  const t0 = Date.now();
  // A 3 s measuring window, sampling the played frames as the drag test samples its counters.
  const playedSamples: number[] = [];
  // At least 3 s, and until 3 frames have played (a loaded machine plays fewer per second).
  while (Date.now() - t0 < 3000 || playedSamples[playedSamples.length - 1]! - played0 < 3)
    playedSamples.push(await page.evaluate(() => (window as any).rigel.timeline.playedFrames.length));
  const end = await page.evaluate(() => (window as any).rigel.stats());
  const played = (await page.evaluate(() => (window as any).rigel.timeline.playedFrames.length)) - played0;
  const elapsed = (Date.now() - t0) / 1000;
  await page.keyboard.press('Space');
  await expect(page.getByTestId('play')).not.toHaveClass(/active/);
  const result = {
    browser: `headless ${testInfo.project.use.browserName ?? 'chromium'}`,
    renderer: end.renderer,
    trailAndGhosts: overlays,
    seconds: Number(elapsed.toFixed(2)),
    framesPlayed: played,
    playedFps: Number((played / elapsed).toFixed(1)),
    renderedFps: Number(((end.frames - start.frames) / elapsed).toFixed(1)),
    posesPerSecond: Number(((end.poses - start.poses) / elapsed).toFixed(1)),
  };
  const file = overlays ? 'play-rate-overlays.json' : 'play-rate.json';
  console.log(`frame rate while playing${overlays ? ' (trail and ghosts on)' : ''}: ${JSON.stringify(result)}`);
  mkdirSync(join(webDir, 'test-results'), { recursive: true });
  writeFileSync(join(webDir, 'test-results', file), JSON.stringify(result, null, 2) + '\n');
  expect(result.framesPlayed).toBeGreaterThanOrEqual(3);
});
