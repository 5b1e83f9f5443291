// POSIX path arithmetic for the files a definition names (its <geo> files
// are relative to the definition's folder): what the page needs to move a
// relative path from one folder to another.

export function isAbsolute(p: string): boolean {
  return p.startsWith('/');
}

/** `.` and `..` resolved, doubled slashes dropped; keeps a leading `/`. */
export function normalize(p: string): string {
  const abs = isAbsolute(p);
  const out: string[] = [];
  for (const part of p.split('/')) {
    if (part === '' || part === '.') continue;
    if (part === '..') {
      if (out.length && out[out.length - 1] !== '..') out.pop();
      else if (!abs) out.push('..');
      continue;
    }
    out.push(part);
  }
  const s = out.join('/');
  return abs ? `/${s}` : s || '.';
}

export function join(base: string, p: string): string {
  return isAbsolute(p) ? normalize(p) : normalize(`${base}/${p}`);
}

export function dirname(p: string): string {
  const n = normalize(p);
  const i = n.lastIndexOf('/');
  if (i < 0) return '.';
  return i === 0 ? '/' : n.slice(0, i);
}

/** The path of absolute `to` from absolute folder `from` (`..` where needed). */
export function relative(from: string, to: string): string {
  const a = normalize(from).split('/').filter(Boolean);
  const b = normalize(to).split('/').filter(Boolean);
  let i = 0;
  while (i < a.length && i < b.length && a[i] === b[i]) i++;
  const up = a.slice(i).map(() => '..');
  return [...up, ...b.slice(i)].join('/') || '.';
}
