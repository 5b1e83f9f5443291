// The Rig Manager: add a rig from a definition, step its build, notice the
// definition changed on disk (red warning), update, remove.

import { readFileSync, writeFileSync } from 'node:fs';
import { join } from 'node:path';
import { expect, test } from './fixtures';

// The biped drives the joints itself: no ephemeral controls on this character.
test.use({ serverOptions: { ephemeral: false, token: 'e2e-token' } });

test('Rig Manager: add, step, out of date, update, remove', async ({ app: page, server, shots }) => {
  await page.getByTestId('tab-rigs').click();
  await expect(page.getByTestId('rig-list')).toContainText('No rig');
  await shots.take('empty');

  await page.getByTestId('rig-add-path').fill('examples/biped.rig.xml');
  await page.getByTestId('rig-add').click();
  const row = page.getByTestId('rig-hero');
  await expect(row).toBeVisible();
  await expect(row).toContainText('v1.0');
  await expect(row).toContainText('biped.rig.xml');
  await expect(row).not.toHaveClass(/out-of-date/);
  await expect(page.getByTestId('rig-warning')).toHaveCount(0);
  const rigs = (await server.get('/api/rigs')).rigs;
  expect(rigs.map((r: any) => r.name)).toEqual(['hero']);
  const steps: number = rigs[0].steps;
  expect(rigs[0].buildPosition).toBe(steps);
  // The viewport now draws the rig's controls too.
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBeGreaterThan(10);
  await shots.take('added');

  // Build stepping.
  await expect(page.getByTestId('step-position')).toHaveText(`${steps} / ${steps}`);
  await page.getByTestId('step-back').click();
  await expect(page.getByTestId('step-position')).toHaveText(`${steps - 1} / ${steps}`);
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].buildPosition).toBe(steps - 1);
  await shots.take('stepped-back');
  await page.getByTestId('step-forward').click();
  await expect(page.getByTestId('step-position')).toHaveText(`${steps} / ${steps}`);

  // Feature toggles: stretch off redoes the build without it, then on again.
  const stretch = page.getByTestId('rig-feature-stretch');
  await expect(stretch).toBeChecked();
  await stretch.uncheck();
  await expect
    .poll(async () => (await server.get('/api/rigs')).rigs[0].features.find((f: any) => f.feature === 'stretch').enabled)
    .toBe(false);
  await shots.take('stretch-off');
  await page.getByTestId('rig-feature-stretch').check();
  await expect
    .poll(async () => (await server.get('/api/rigs')).rigs[0].features.find((f: any) => f.feature === 'stretch').enabled)
    .toBe(true);

  // A newer definition on disk: the rig turns red with a warning.
  const file = join(server.root, 'examples/biped.rig.xml');
  const xml = readFileSync(file, 'utf8');
  const newer = xml
    .replace('<rig name="hero" version="1.0">', '<rig name="hero" version="1.1">')
    .replace(
      /(<component type="eye" name="eyes" side="C" version=")1\.0(")/,
      '$11.1$2',
    )
    .replace('<param name="aimDistance" value="0.4"/>', '<param name="aimDistance" value="0.5"/>');
  expect(newer).not.toEqual(xml);
  writeFileSync(file, newer);
  await expect(row).toHaveClass(/out-of-date/, { timeout: 8000 });
  await expect(page.getByTestId('rig-warning')).toBeVisible();
  await expect(page.getByTestId('rig-warning')).toContainText('1.1');
  await expect(page.getByTestId('rig-update')).toHaveClass(/danger/);
  const warnColor = await row.evaluate((el) => getComputedStyle(el).borderTopColor);
  expect(warnColor).toBe('rgb(255, 92, 92)');
  await shots.take('out-of-date');

  // Update, keeping the world positions of keys.
  await page.getByTestId('rig-keep-world').check();
  await page.getByTestId('rig-update').click();
  await expect(row).not.toHaveClass(/out-of-date/);
  await expect(row).toContainText('v1.1');
  await expect(page.getByTestId('rig-warning')).toHaveCount(0);
  const updated = (await server.get('/api/rigs')).rigs[0];
  expect(updated.version).toBe('1.1');
  expect(updated.outOfDate).toBe(false);
  await shots.take('updated');

  // Rig edit mode on the built rig, and back out of it.
  await page.getByTestId('rig-enter-edit').click();
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].editMode).toBe(true);
  await expect(row).toContainText('EDIT');
  await shots.take('edit-mode');
  await page.getByTestId('rig-leave-edit').click();
  await expect.poll(async () => (await server.get('/api/rigs')).rigs[0].editMode).toBe(false);

  // Remove.
  await page.getByTestId('rig-remove').click();
  await expect(page.getByTestId('rig-list')).toContainText('No rig');
  expect((await server.get('/api/rigs')).rigs).toEqual([]);
  await expect
    .poll(() => page.evaluate(() => (window as any).rigel.app.nodes.controls.filter((c: any) => c.rig === 'hero').length))
    .toBe(0);
  await shots.take('removed');
  expect(await page.evaluate(() => (window as any).rigel.errors)).toEqual([]);
});

test('Rig Manager: a missing definition is reported in the status bar', async ({ app: page }) => {
  await page.getByTestId('rig-add-path').fill('examples/nope.rig.xml');
  await page.getByTestId('rig-add').click();
  await expect(page.locator('#statusbar')).toHaveClass(/error/);
  await expect(page.getByTestId('status-text')).toContainText('/api/rigs/add');
  // Paths that leave the root are refused (400).
  await page.getByTestId('rig-add-path').fill('../../etc/passwd');
  await page.getByTestId('rig-add').click();
  await expect(page.getByTestId('status-text')).toContainText('400');
});
