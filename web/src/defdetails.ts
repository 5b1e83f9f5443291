// The details panel of the definition editor: the fields of the selected
// node, generated from its component's schema (GET /api/components):
// name, side, version, attach hook, guides, parameters, control looks; for
// the Rig node its name, version and geometry. Each field writes the model
// (defmodel.ts) and tells the editor what it edited.

import type { ParamSchema } from './api';
import { DefinitionModel } from './defmodel';
import type { GNode, Side } from './defmodel';
import { h, fill } from './dom';

const kShapes = [
  'circle', 'square', 'cube', 'sphere', 'diamond', 'cross', 'arrow', 'doubleArrow',
  'fourArrow', 'fourArrowCircle', 'locator', 'pin', 'triangle',
];

export interface DetailsContext {
  model: DefinitionModel;
  /**
   * A field of `n` changed: its box is drawn again, the details too when
   * `structural` (rows added or removed), and the definition validated or
   * built when `n` is part of it.
   */
  edited(n: GNode, structural?: boolean): void;
  detach(id: string): void;
  remove(id: string): void;
  error(text: string): void;
}

/** Fills `el` with the fields of `n` (nothing when no node is selected). */
export function renderDetails(el: HTMLElement, n: GNode | undefined, ctx: DetailsContext): void {
  if (!n) {
    fill(el);
    return;
  }
  if (n.kind === 'rig') fill(el, ...rigDetails(n, ctx));
  else fill(el, ...componentDetails(n, ctx));
}

function textField(label: string, value: string, set: (v: string) => void, edited: () => void, testid: string, extra: Record<string, unknown> = {}): HTMLElement {
  const input = h('input', { type: 'text', value, testid, ...extra });
  input.addEventListener('change', () => {
    set(input.value);
    edited();
  });
  return h('label.field', {}, h('span', {}, label), input);
}

function rigDetails(n: GNode, ctx: DetailsContext): HTMLElement[] {
  const edited = (structural = false): void => ctx.edited(n, structural);
  const geometryEdited = (structural = false): void => {
    ctx.model.geometrySet = true;
    edited(structural);
  };
  return [
    h('h3', {}, 'Rig'),
    textField('Name', n.name, (v) => (n.name = v.trim()), edited, 'def-rig-name'),
    textField('Version', n.version, (v) => (n.version = v.trim()), edited, 'def-rig-version'),
    h('h4', {}, 'Geometry'),
    h('div.hint', {}, 'The character files the rig is built on (<geo>); saved relative to the definition’s folder.'),
    ...n.geometry.map((g, i) => {
      const file = h('input', { type: 'text', value: g.file, placeholder: 'character file', testid: `def-geo-file-${i}` });
      file.addEventListener('change', () => {
        g.file = file.value.trim();
        geometryEdited();
      });
      const mesh = h('input', { type: 'text', value: g.name, placeholder: 'mesh (optional)', testid: `def-geo-name-${i}` });
      mesh.addEventListener('change', () => {
        g.name = mesh.value.trim();
        geometryEdited();
      });
      return h('div.guide-row', {}, file, mesh);
    }),
    h(
      'div.button-row',
      {},
      h('button.small', {
        testid: 'def-geo-add',
        onclick: () => {
          n.geometry.push({ file: '', name: '' });
          geometryEdited(true);
        },
      }, '+ geometry'),
      h('button.small', {
        disabled: !n.geometry.length, testid: 'def-geo-remove',
        onclick: () => {
          n.geometry.pop();
          geometryEdited(true);
        },
      }, '− geometry'),
    ),
    h('div.hint', {}, `${ctx.model.children(n.id).length} root component(s). Saving over a file with other content bumps the version.`),
  ];
}

function componentDetails(n: GNode, ctx: DetailsContext): (HTMLElement | HTMLElement[] | null)[] {
  const edited = (structural = false): void => ctx.edited(n, structural);
  const schema = ctx.model.schemas.get(n.type);
  const side = h('select', { testid: 'def-side' }, (['C', 'L', 'R'] as Side[]).map((s) => h('option', { value: s, selected: n.side === s }, s)));
  side.addEventListener('change', () => {
    n.side = side.value as Side;
    edited();
  });
  const parent = n.parent ? ctx.model.nodes.get(n.parent) : undefined;
  const hooks = parent?.kind === 'component' ? ctx.model.hooksOf(parent) : [];
  const attachList = `hooks-${n.id}`;
  const attach = parent?.kind === 'component'
    ? [
        textField('Attach', n.attach, (v) => (n.attach = v), edited, 'def-attach', { list: attachList, placeholder: hooks[0] ? `${hooks[0]} (hook 0)` : 'hook 0' }),
        h('datalist', { id: attachList }, hooks.map((x) => h('option', { value: x }))),
      ]
    : null;
  const canAdd = !schema || schema.guides.max < 0 || n.guides.length < schema.guides.max;
  const canRemove = !schema || n.guides.length > schema.guides.min;
  const guideCount = schema ? `(${schema.guides.min}${schema.guides.max < 0 ? '+' : schema.guides.max !== schema.guides.min ? `–${schema.guides.max}` : ''})` : '';

  return [
    h('h3', {}, `${n.type} component`),
    schema ? h('div.hint', {}, schema.help) : null,
    textField('Name', n.name, (v) => (n.name = v.trim()), edited, 'def-name'),
    h('label.field', {}, h('span', {}, 'Side'), side),
    textField('Version', n.version, (v) => (n.version = v.trim()), edited, 'def-version'),
    h('label.field', {}, h('span', {}, 'rigId'), h('code.rigid', {}, n.rigId)),
    attach,
    h('h4', {}, `Guides ${guideCount}`),
    schema?.guides.help ? h('div.hint', {}, schema.guides.help) : null,
    guideRows(n, ctx),
    h(
      'div.button-row',
      {},
      h('button.small', {
        disabled: !canAdd, testid: 'def-guide-add',
        onclick: () => {
          const i = n.guides.length;
          n.guides.push({ name: schema?.guides.names[i] ?? '', joint: '', translate: [0, 0, 0], extra: {} });
          edited(true);
        },
      }, '+ guide'),
      h('button.small', {
        disabled: !canRemove, testid: 'def-guide-remove',
        onclick: () => {
          n.guides.pop();
          edited(true);
        },
      }, '− guide'),
    ),
    schema?.params.length ? h('h4', {}, 'Parameters') : null,
    (schema?.params ?? []).map((p) => paramField(n, p, ctx)),
    schema?.controls.length ? h('h4', {}, 'Controls') : null,
    controlRows(n, ctx),
    h(
      'div.button-row',
      {},
      n.parent ? h('button.small', { testid: 'def-detach', onclick: () => ctx.detach(n.id) }, 'Detach from parent') : null,
      h('button.small.danger-outline', { testid: 'def-delete', onclick: () => ctx.remove(n.id) }, 'Delete node'),
    ),
  ];
}

function guideRows(n: GNode, ctx: DetailsContext): HTMLElement[] {
  const schema = ctx.model.schemas.get(n.type);
  const edited = (): void => ctx.edited(n);
  return n.guides.map((g, i) => {
    const fixed = schema?.guides.names[i];
    const joint = h('input', { type: 'text', value: g.joint, list: 'joint-names', placeholder: 'joint (empty: use translate)', testid: `def-guide-joint-${i}` });
    joint.addEventListener('change', () => {
      g.joint = joint.value.trim();
      edited();
    });
    const name = fixed
      ? h('span.guide-name', {}, fixed)
      : h('input.guide-name', { type: 'text', value: g.name, placeholder: `guide ${i}`, testid: `def-guide-name-${i}` });
    if (name instanceof HTMLInputElement) {
      name.addEventListener('change', () => {
        g.name = name.value.trim();
        edited();
      });
    }
    const xyz = g.translate.map((v, k) => {
      const input = h('input.num', { type: 'number', step: '0.01', value: String(v), title: `translate ${'xyz'[k]}` });
      input.addEventListener('change', () => {
        g.translate[k] = Number(input.value) || 0;
        edited();
      });
      return input;
    });
    return h('div.guide-row', {}, name, joint, h('span.xyz', {}, xyz));
  });
}

function controlRows(n: GNode, ctx: DetailsContext): HTMLElement[] {
  const schema = ctx.model.schemas.get(n.type);
  return (schema?.controls ?? []).map((c) => {
    const look = n.controls[c.role] ?? { shape: '', color: '', size: null };
    const store = (): void => {
      n.controls[c.role] = look;
      ctx.edited(n);
    };
    const shape = h('select', { title: 'shape' }, h('option', { value: '' }, `${c.shape} (default)`), kShapes.map((s) => h('option', { value: s, selected: look.shape === s }, s)));
    shape.addEventListener('change', () => {
      look.shape = shape.value;
      store();
    });
    const color = h('input', { type: 'text', value: look.color, placeholder: c.color, title: 'palette name or #rrggbb' });
    color.addEventListener('change', () => {
      look.color = color.value.trim();
      store();
    });
    const size = h('input.num', { type: 'number', step: '0.01', min: '0.001', value: look.size === null ? '' : String(look.size), placeholder: String(c.size), title: 'size' });
    size.addEventListener('change', () => {
      look.size = size.value === '' ? null : Number(size.value);
      store();
    });
    return h('div.control-row', { title: c.help }, h('span.role', {}, c.role), shape, color, size);
  });
}

function paramField(n: GNode, p: ParamSchema, ctx: DetailsContext): HTMLElement {
  const isSet = p.name in n.params;
  const value = isSet ? n.params[p.name] : p.default;
  const set = (v: unknown): void => {
    DefinitionModel.setParam(n, p, v);
    ctx.edited(n);
  };
  const range = p.min !== undefined || p.max !== undefined ? ` [${p.min ?? '−∞'}, ${p.max ?? '∞'}]` : '';
  let input: HTMLElement;
  const testid = `def-param-${p.name}`;
  switch (p.type) {
    case 'bool': {
      const c = h('input', { type: 'checkbox', checked: value === true, testid });
      c.addEventListener('change', () => set(c.checked));
      input = c;
      break;
    }
    case 'enum': {
      const s = h('select', { testid }, (p.choices ?? []).map((ch) => h('option', { value: ch, selected: ch === value }, ch)));
      s.addEventListener('change', () => set(s.value));
      input = s;
      break;
    }
    case 'int':
    case 'double': {
      const i = h('input.num', { type: 'number', step: p.type === 'int' ? '1' : 'any', value: String(value ?? ''), testid });
      if (p.min !== undefined) i.min = String(p.min);
      if (p.max !== undefined) i.max = String(p.max);
      i.addEventListener('change', () => {
        const v = Number(i.value);
        if (i.value === '' || !Number.isFinite(v)) {
          ctx.error(`${p.name}: not a number`);
          return;
        }
        if ((p.min !== undefined && v < p.min) || (p.max !== undefined && v > p.max)) {
          ctx.error(`${p.name}: ${v} is out of range${range}`);
        }
        set(p.type === 'int' ? Math.round(v) : v);
      });
      input = i;
      break;
    }
    case 'vec3': {
      const v = (Array.isArray(value) ? value : [0, 0, 0]) as number[];
      const inputs = [0, 1, 2].map((k) => h('input.num', { type: 'number', step: 'any', value: String(v[k] ?? 0) }));
      for (const i of inputs) i.addEventListener('change', () => set(inputs.map((x) => Number(x.value) || 0)));
      input = h('span.xyz', { testid }, inputs);
      break;
    }
    default: {
      const t = h('input', { type: 'text', value: String(value ?? ''), testid });
      t.addEventListener('change', () => set(t.value));
      input = t;
    }
  }
  const reset = isSet
    ? h('button.link', {
        title: `Back to the default (${JSON.stringify(p.default)})`,
        onclick: () => {
          delete n.params[p.name];
          ctx.edited(n, true);
        },
      }, '↺')
    : null;
  return h('label.field', { title: p.help ?? '' }, h('span', {}, `${p.name}`, h('small', {}, ` ${p.type}${range}`)), input, reset);
}
