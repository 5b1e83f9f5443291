// What the page reads again after a change (src/commands.ts: each command
// names what it can affect): a selection its keys, a frame its pose
// (refresh-definition.spec.ts: a saved definition the rigs).

import type { Page, Request } from '@playwright/test';
import { clickControl, expect, expectSelection, settle, test } from './fixtures';

/** The API routes the page requests while `action` runs and the page settles, but the revision poller's. */
async function routesDuring(page: Page, settled: () => Promise<void>, action: () => Promise<void>): Promise<string[]> {
  const routes: string[] = [];
  const seen = (r: Request): void => {
    const path = new URL(r.url()).pathname;
    if (path.startsWith('/api/') && path !== '/api/revision') routes.push(`${r.method()} ${path}`);
  };
  page.on('request', seen);
  try {
    await action();
    await settled();
  } finally {
    page.off('request', seen);
  }
  return [...new Set(routes)].sort();
}

test('a selection re-reads the keys and a frame the pose, nothing else', async ({ app: page, server }) => {
  // The Rig Manager refetches the rigs while it is shown: show the editor instead.
  await page.getByTestId('tab-def').click();
  await settle(page, server);
  const selected = await routesDuring(
    page,
    () => settle(page, server),
    async () => {
      await clickControl(page, 'hand.L_ctrl');
      await expectSelection(page, server, ['hand.L_ctrl']);
    },
  );
  expect(selected).toEqual(['GET /api/keys', 'POST /api/select']);

  const moved = await routesDuring(
    page,
    () => settle(page, server),
    async () => {
      await page.getByTestId('frame').fill('4');
      await page.getByTestId('frame').press('Enter');
      await expect.poll(async () => (await server.get('/api/scene')).frame).toBe(4);
    },
  );
  expect(moved).toEqual(['GET /api/keys', 'GET /api/pose', 'POST /api/time']);
  await expect(page.getByTestId('frame')).toHaveValue('4');
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
