// End-to-end tests of the web app against a real `rigel serve` (e2e/fixtures.ts
// starts one per test), in Debian's chromium: never `npx playwright install`.
import { defineConfig } from '@playwright/test';

export default defineConfig({
  testDir: './e2e',
  outputDir: './test-results',
  // Generous: the suite runs on two shared cores with software WebGL
  // (SwiftShader). Tests wait on state, never on time: a limit only bounds
  // how long a broken test takes to fail.
  timeout: 180_000,
  expect: { timeout: 30_000 },
  // One scene per test and two shared cores: tests run one after the other.
  workers: 1,
  fullyParallel: false,
  retries: 0,
  reporter: [['list'], ['html', { open: 'never', outputFolder: 'playwright-report' }]],
  use: {
    browserName: 'chromium',
    headless: true,
    viewport: { width: 1400, height: 860 },
    screenshot: 'only-on-failure',
    trace: 'retain-on-failure',
    launchOptions: {
      executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
      args: [
        '--no-sandbox',
        '--disable-gpu',
        '--disable-quic',
        '--no-first-run',
        '--disable-background-networking',
        '--disable-component-update',
        '--disable-sync',
        // WebGL without a GPU: ANGLE on SwiftShader (software).
        '--use-angle=swiftshader',
        '--enable-unsafe-swiftshader',
      ],
    },
  },
});
