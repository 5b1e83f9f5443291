// The camera on load keeps the whole character in view: the top of the
// head (the top of the skinned mesh in its posed box, above the last
// joint) and the feet lie inside the canvas, and the character fills a
// sane part of its height. Checked on the body and on CesiumMan (whose head
// the joints-only framing cut off) and a character with no controls.

import { expect, settle, startServer, test } from './fixtures';
import type { Page } from '@playwright/test';

async function expectFramed(page: Page): Promise<void> {
  const canvas = (await page.getByTestId('viewport-canvas').boundingBox())!;
  const box = (await page.evaluate(() => (window as any).rigel.viewport.meshScreenBox())) as {
    left: number; top: number; right: number; bottom: number;
  } | null;
  expect(box).not.toBeNull();
  expect(box!.top).toBeGreaterThanOrEqual(canvas.y);
  expect(box!.bottom).toBeLessThanOrEqual(canvas.y + canvas.height);
  expect(box!.left).toBeGreaterThanOrEqual(canvas.x);
  expect(box!.right).toBeLessThanOrEqual(canvas.x + canvas.width);
  expect(box!.bottom - box!.top).toBeGreaterThan(0.4 * canvas.height);
}

test('the body is framed on load', async ({ app: page, shots }) => {
  await expectFramed(page);
  await shots.take('body-framed');
});

for (const [file, ephemeral] of [['tests/data/gltf/CesiumMan.glb', true], ['tests/data/gltf/RiggedFigure.glb', false]] as const)
  test(`${file.split('/').pop()} is framed on load, head to feet`, async ({ page }, testInfo) => {
    const server = await startServer({ ephemeral, token: 'e2e-token', character: file });
    try {
      await page.goto(server.pageUrl());
      await page.waitForFunction(() => (window as any).rigel?.isReady?.() === true, null, { timeout: 60_000 });
      await settle(page, server);
      await expectFramed(page);
      await page.screenshot({ path: testInfo.outputPath('01-framed.png') });
    } finally {
      await server.stop();
    }
  });
