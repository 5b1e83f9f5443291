// The build-graph editor's details panel and variables: the fields of the
// selected node, or the rig's settings when none is. A component node's
// component is edited in the definition editor's fields (defdetails.ts on a
// loose node of a DefinitionModel, written back in the `.rig.json` syntax),
// its parent the component node linked into its `parent` input, and the
// inputs links feed shown linked, read-only. Constants show their value,
// variables' get and set their variable, branches and functions the values
// of their unlinked inputs, each field by the socket's type. Every field
// writes the model (buildgraphmodel.ts) and tells the editor what it edited.

import { renderDetails } from './defdetails';
import type { DetailsContext } from './defdetails';
import { DefinitionModel } from './defmodel';
import type { GraphSocket } from './api';
import { kStart, linkKey, refText, zeroOf } from './buildgraphmodel';
import type { BuildGraphModel, GraphNode } from './buildgraphmodel';
import { h, fill } from './dom';

export interface GraphDetailsContext {
  model: BuildGraphModel;
  /**
   * A field of node `n` changed: its box is drawn again (the details too
   * when `structural`: rows added or removed), and the graph validated or
   * built.
   */
  nodeEdited(n: GraphNode, structural?: boolean): void;
  /**
   * Something more than one box shows changed (the rig's settings, a
   * variable, the variable a node names): everything is drawn again, and
   * the graph validated or built unless `build` is false.
   */
  graphEdited(build?: boolean): void;
  disconnect(key: string): void;
  remove(id: string): void;
  error(text: string): void;
}

/** Fills `el` with the fields of `n`, or the rig's settings when no node is selected. */
export function renderGraphDetails(el: HTMLElement, n: GraphNode | undefined, ctx: GraphDetailsContext): void {
  if (!n) {
    fill(el, rigDetails(ctx));
    return;
  }
  const kind = ctx.model.kindOf(n);
  fill(
    el,
    h('h3', {}, `${kind?.niceName ?? n.kind} node`),
    h('div.hint', {}, h('code', { testid: 'bg-node-id' }, n.id), ` · ${n.kind}${kind?.help ? ` · ${kind.help}` : ''}`),
    n.component ? componentDetails(n, ctx) : nodeDetails(n, ctx),
    n.id !== kStart && !n.component
      ? h('div.button-row', {}, h('button.small.danger-outline', { testid: 'bg-delete', onclick: () => ctx.remove(n.id) }, 'Delete node'))
      : null,
  );
}

/** The rig's settings: name, version and the character files it is built on. */
function rigDetails(ctx: GraphDetailsContext): HTMLElement[] {
  const { model } = ctx;
  const rig = model.rig;
  const geometryEdited = (build = true): void => {
    model.geometrySet = true;
    ctx.graphEdited(build);
  };
  const geometry = rig.geometry.map((g, i) =>
    h(
      'div.guide-row',
      {},
      textInput(g.file, 'character file', `bg-geo-file-${i}`, (v) => {
        g.file = v;
        geometryEdited();
      }),
      textInput(g.name, 'mesh (optional)', `bg-geo-name-${i}`, (v) => {
        g.name = v;
        geometryEdited();
      }),
    ),
  );
  return [
    h('h3', {}, 'Rig'),
    field('Name', textInput(rig.name, 'rig', 'bg-rig-name', (v) => {
      rig.name = v || 'rig';
      ctx.graphEdited();
    })),
    field('Version', textInput(rig.version, '1.0', 'bg-rig-version', (v) => {
      rig.version = v || '1.0';
      ctx.graphEdited();
    })),
    h('h4', {}, 'Geometry'),
    h('div.hint', {}, 'The character files the rig is built on; saved relative to the graph’s folder.'),
    ...geometry,
    h(
      'div.button-row',
      {},
      h('button.small', {
        testid: 'bg-geo-add',
        onclick: () => {
          rig.geometry.push({ file: '', name: '' });
          geometryEdited(false);
        },
      }, '+ geometry'),
      h('button.small', {
        testid: 'bg-geo-remove',
        disabled: !rig.geometry.length,
        onclick: () => {
          rig.geometry.pop();
          geometryEdited();
        },
      }, '− geometry'),
    ),
    h('div.hint', {}, `${model.nodes.size} node(s), ${model.links.length} link(s). Saving over a file with other content bumps the version.`),
  ];
}

/**
 * A component node: its component in the definition editor's fields, its
 * parent the component node linked into `parent` (so the attach field lists
 * that component's hooks, and "Detach" removes the link).
 */
function componentDetails(n: GraphNode, ctx: GraphDetailsContext): HTMLElement {
  const box = h('div.def-details');
  const defs = new DefinitionModel();
  defs.schemas = ctx.model.schemas;
  const parentLink = ctx.model.linkInto({ node: n.id, socket: 'parent' });
  const parent = parentLink ? ctx.model.nodes.get(parentLink.from.node)?.component : null;
  const original = n.component!;
  const g = defs.looseComponent(original);
  if (parent) g.parent = defs.looseComponent(parent).id;
  const details: DetailsContext = {
    model: defs,
    edited: (node, structural = false) => {
      const { guiLocation: _gui, ...c } = defs.componentJson(node);
      // A component without a rigId keeps none: the server makes it from the rig's name and the node's id.
      if (!original.rigId) delete c.rigId;
      n.component = c;
      ctx.nodeEdited(n, structural);
    },
    detach: () => parentLink && ctx.disconnect(linkKey(parentLink)),
    remove: () => ctx.remove(n.id),
    error: (text) => ctx.error(text),
  };
  renderDetails(box, g, details);
  markLinked(box, n, ctx.model);
  return box;
}

/** The details panel's field of a component input (defdetails.ts's test ids). */
function detailsFieldId(socket: string): string {
  return ['name', 'side', 'attach'].includes(socket) ? `def-${socket}` : `def-param-${socket}`;
}

/** Disables the fields of a component node's inputs that links feed, naming the output. */
function markLinked(box: HTMLElement, n: GraphNode, model: BuildGraphModel): void {
  for (const s of model.inputsOf(n)) {
    const l = model.linkInto({ node: n.id, socket: s.name });
    if (!l || s.type === 'exec' || s.name === 'parent') continue;
    const input = box.querySelector<HTMLElement>(`[data-testid="${detailsFieldId(s.name)}"]`);
    const label = input?.closest<HTMLElement>('label.field');
    if (!input || !label) continue;
    for (const x of [input, ...input.querySelectorAll<HTMLElement>('input, select')]) {
      if (x instanceof HTMLInputElement || x instanceof HTMLSelectElement) x.disabled = true;
    }
    label.classList.add('linked');
    label.dataset.linked = refText(l.from);
    label.title = `Linked from ${refText(l.from)}: the value that reaches it`;
    label.append(h('span.linked-from', { testid: `bg-linked-${s.name}` }, `← ${refText(l.from)}`));
  }
}

/** Constants, variables' get and set, branches and functions: their value and unlinked inputs. */
function nodeDetails(n: GraphNode, ctx: GraphDetailsContext): (HTMLElement | null)[] {
  const out: (HTMLElement | null)[] = [];
  if (n.kind.startsWith('constant:')) {
    const set = (v: unknown): void => {
      n.value = v;
      ctx.nodeEdited(n);
    };
    out.push(field('Value', valueInput(n.kind.slice('constant:'.length), n.value, 'bg-value', set)));
  }
  if (n.kind === 'variable:get' || n.kind === 'variable:set') out.push(variableSelect(n, ctx));
  if (n.kind.startsWith('function:')) {
    const set = (v: string): void => {
      n.rigId = v;
      ctx.nodeEdited(n);
    };
    out.push(field('rigId', textInput(n.rigId, 'made from the rig and the node', 'bg-rigid', set)));
  }
  for (const s of ctx.model.inputsOf(n)) {
    if (s.type !== 'exec') out.push(inputField(n, s, ctx));
  }
  if (!ctx.model.kindOf(n)) out.push(h('div.hint', {}, `A node kind this server does not have, kept as it came: ${JSON.stringify(n.values)}`));
  return out;
}

function variableSelect(n: GraphNode, ctx: GraphDetailsContext): HTMLElement {
  const names = ctx.model.variables.map((v) => v.name);
  const select = h(
    'select',
    { testid: 'bg-variable' },
    h('option', { value: '', selected: !n.variable }, names.length ? '(pick a variable)' : '(add a variable below)'),
    n.variable && !names.includes(n.variable) ? h('option', { value: n.variable, selected: true }, `${n.variable} (missing)`) : null,
    names.map((v) => h('option', { value: v, selected: v === n.variable }, v)),
  );
  select.addEventListener('change', () => {
    n.variable = select.value;
    // Its sockets' type (and colour) follow the variable's.
    ctx.graphEdited();
  });
  return field('Variable', select);
}

/** An input of a node other than a component: linked (read-only), one to link (a component), or its value. */
function inputField(n: GraphNode, s: GraphSocket, ctx: GraphDetailsContext): HTMLElement {
  const ref = { node: n.id, socket: s.name };
  const l = ctx.model.linkInto(ref);
  const type = ctx.model.socketType(ref, 'in');
  if (l) return field(s.name, h('span.linked-from', { testid: `bg-linked-${s.name}` }, `← ${refText(l.from)}`), s.help);
  if (!type || !ctx.model.types.get(type)?.value) {
    return field(s.name, h('span.hint', {}, type ? `link a ${type} output` : 'pick a variable'), s.help);
  }
  const input = valueInput(type, ctx.model.inputValue(n, s.name), `bg-input-${s.name}`, (v) => {
    ctx.model.setInputValue(n, s.name, v);
    ctx.nodeEdited(n);
  });
  return field(s.name, input, s.help);
}

// --------------------------------------------------------------- variables

/** Fills `el` with the graph's variables (name, type, value when the build starts, remove) and a row to add one. */
export function renderVariables(el: HTMLElement, ctx: GraphDetailsContext): void {
  const { model } = ctx;
  const types = model.variableTypes().map((t) => t.name);
  const typeSelect = (value: string, testid: string): HTMLSelectElement =>
    h('select', { testid }, (types.length ? types : [value]).map((t) => h('option', { value: t, selected: t === value }, t)));
  const rows = model.variables.map((v, i) => {
    const type = typeSelect(v.type, `bg-var-type-${i}`);
    type.addEventListener('change', () => {
      model.setVariableType(v.name, type.value);
      ctx.graphEdited();
    });
    const name = textInput(v.name, 'name', `bg-var-name-${i}`, (to) => {
      const problem = model.renameVariable(v.name, to);
      if (problem) ctx.error(`Variable: ${problem}`);
      ctx.graphEdited(!problem);
    });
    const value = valueInput(v.type, v.value, `bg-var-value-${i}`, (x) => {
      v.value = x;
      ctx.graphEdited();
    });
    const remove = h('button.link', {
      title: `Remove ${v.name} (the nodes naming it stay, and are reported)`,
      testid: `bg-var-remove-${i}`,
      onclick: () => {
        model.removeVariable(v.name);
        ctx.graphEdited();
      },
    }, '✕');
    return h('div.bg-var-row', { testid: `bg-var-${v.name}` }, name, type, value, remove);
  });
  fill(
    el,
    rows.length ? rows : h('div.hint', {}, 'No variables: a Set node gives one a new value, a Get node reads it.'),
    newVariableRow(ctx, typeSelect(types[0] ?? 'number', 'bg-var-new-type')),
  );
}

/** The row that adds a variable: its name, its type and its value when the build starts. */
function newVariableRow(ctx: GraphDetailsContext, type: HTMLSelectElement): HTMLElement {
  const name = h('input', { type: 'text', placeholder: 'new variable', testid: 'bg-var-new-name' });
  let value = zeroOf(type.value);
  const valueField = (): HTMLElement =>
    valueInput(type.value, value, 'bg-var-new-value', (v) => {
      value = v;
    });
  let shown = valueField();
  type.addEventListener('change', () => {
    value = zeroOf(type.value);
    const next = valueField();
    shown.replaceWith(next);
    shown = next;
  });
  const add = h('button.small', {
    testid: 'bg-var-add',
    onclick: () => {
      const problem = ctx.model.addVariable(name.value.trim(), type.value, value);
      if (problem) ctx.error(`Variable: ${problem}`);
      else ctx.graphEdited();
    },
  }, '+ variable');
  return h('div.bg-var-row.bg-var-new', {}, name, type, shown, add);
}

// ------------------------------------------------------------------ fields

/** A value as a node's box shows it. */
export function valueText(v: unknown): string {
  if (Array.isArray(v)) return `(${v.map((x) => (typeof x === 'number' ? String(+x.toFixed(3)) : valueText(x))).join(', ')})`;
  if (typeof v === 'string') return JSON.stringify(v);
  return v === undefined ? '' : String(v);
}

function field(label: string, input: HTMLElement, help = ''): HTMLElement {
  return h('label.field', { title: help }, h('span', {}, label), input);
}

/** A text field that sets on change (Enter or leaving it). */
function textInput(value: string, placeholder: string, testid: string, set: (v: string) => void): HTMLInputElement {
  const input = h('input', { type: 'text', value, placeholder, testid });
  input.addEventListener('change', () => set(input.value.trim()));
  return input;
}

/**
 * The field of a value of a data type: a checkbox (bool), a number (int, number), three numbers (vector), a list of
 * its element's fields with a button to add one and one to remove each (list:TYPE), or text.
 */
function valueInput(type: string, value: unknown, testid: string, set: (v: unknown) => void): HTMLElement {
  if (type.startsWith('list:')) return listInput(type.slice('list:'.length), value, testid, set);
  if (type === 'component') return h('span.hint', { testid, title: 'A Set node gives it a component node\'s output' }, 'none');
  switch (type) {
    case 'bool': {
      const c = h('input', { type: 'checkbox', checked: value === true, testid });
      c.addEventListener('change', () => set(c.checked));
      return c;
    }
    case 'int':
    case 'number': {
      const i = h('input.num', { type: 'number', step: type === 'int' ? '1' : 'any', value: String(value ?? 0), testid });
      i.addEventListener('change', () => {
        const v = Number(i.value);
        if (i.value === '' || !Number.isFinite(v)) return;
        set(type === 'int' ? Math.round(v) : v);
      });
      return i;
    }
    case 'vector': {
      const v = (Array.isArray(value) ? value : [0, 0, 0]) as number[];
      const inputs = [0, 1, 2].map((k) => h('input.num', { type: 'number', step: 'any', value: String(v[k] ?? 0), testid: `${testid}-${k}`, title: 'xyz'[k] }));
      for (const i of inputs) i.addEventListener('change', () => set(inputs.map((x) => Number(x.value) || 0)));
      return h('span.xyz', { testid }, inputs);
    }
    default: {
      const t = h('input', { type: 'text', value: typeof value === 'string' ? value : JSON.stringify(value ?? ''), testid });
      t.addEventListener('change', () => set(t.value));
      return t;
    }
  }
}

/** The items of a list value, one field each, and buttons to add an item (its type's zero) or remove one. */
function listInput(element: string, value: unknown, testid: string, set: (v: unknown) => void): HTMLElement {
  const items = Array.isArray(value) ? [...(value as unknown[])] : [];
  const box = h('span.bg-list', { testid });
  const draw = (): void => {
    const rows = items.map((item, i) =>
      h(
        'span.bg-list-item',
        { testid: `${testid}-item-${i}` },
        valueInput(element, item, `${testid}-${i}`, (v) => {
          items[i] = v;
          set([...items]);
        }),
        h('button.link', {
          title: 'Remove this item',
          testid: `${testid}-remove-${i}`,
          onclick: (e: Event) => {
            e.preventDefault();
            items.splice(i, 1);
            set([...items]);
            draw();
          },
        }, '✕'),
      ),
    );
    const add = h('button.small', {
      testid: `${testid}-add`,
      onclick: (e: Event) => {
        e.preventDefault();
        items.push(zeroOf(element));
        set([...items]);
        draw();
      },
    }, '+ item');
    fill(box, rows, add);
  };
  draw();
  return box;
}
