// A saved definition re-reads the rigs (src/commands.ts): a rig built from
// that file may now be out of date, which no revision says, and the Rig
// Manager's periodic refetch runs only while it is shown.

import { expect, settle, test } from './fixtures';

// The biped drives the joints itself: no ephemeral controls on this character.
test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

test('saving a definition re-reads the rigs: the rig built from that file shows it is out of date', async ({ app: page, server }) => {
  await page.getByTestId('rig-add-path').fill('examples/biped.rig.xml');
  await page.getByTestId('rig-add').click();
  await expect(page.getByTestId('rig-hero')).toBeVisible();
  await settle(page, server);
  const before = (await server.get('/api/rigs')).rigs[0];
  expect(before.outOfDate).toBe(false);

  // Saved over its own file (the editor adds node places: other content, a new version).
  await page.getByTestId('rig-open-definition').click();
  await expect(page.getByTestId('def-save-path')).toHaveValue('examples/biped.rig.xml');
  await page.getByTestId('def-save').click();
  await expect(page.getByTestId('status-text')).toContainText('Saved');
  await settle(page, server);
  const after = (await server.get('/api/rigs')).rigs;
  expect(after[0].definitionVersion).not.toBe(before.definitionVersion);
  // The Rig Manager is hidden (no periodic refetch) and no revision changed: the save's own re-read.
  expect(await page.evaluate(() => (window as any).rigel.app.rigs)).toEqual(after);
  await page.getByTestId('tab-rigs').click();
  await expect(page.getByTestId('rig-hero')).toHaveClass(/out-of-date/);
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});
