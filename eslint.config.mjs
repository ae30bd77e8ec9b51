// ESLint 9 flat config for the report page (browser script, uPlot as a global) and its
// headless-browser tests (Node 18 ES modules): `npx eslint src/report/web tests/report/browser`
import js from '@eslint/js';
import globals from 'globals';

export default [
  { ignores: ['node_modules/**', 'build*/**', 'bench/**', 'out/**'] },
  js.configs.recommended,
  {
    files: ['src/report/web/**/*.js'],
    languageOptions: {
      ecmaVersion: 2022,
      sourceType: 'script',
      globals: { ...globals.browser, uPlot: 'readonly' },
    },
  },
  {
    files: ['tests/report/browser/**/*.mjs'],
    languageOptions: {
      ecmaVersion: 2022,
      sourceType: 'module',
      // page.evaluate() callbacks run in the page: the few browser globals they use
      globals: { ...globals.node, window: 'readonly', document: 'readonly', getComputedStyle: 'readonly' },
    },
  },
  {
    rules: {
      'no-unused-vars': ['error', { args: 'none' }],
      eqeqeq: ['error', 'always', { null: 'ignore' }],
    },
  },
];
