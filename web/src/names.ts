// The names the user knows, in the messages of the server: a message names
// a channel by its attribute (`hand.L_ctrl.rotateQuaternion is keyed and
// frame 10 has no key`) and a node by its uuid at times; the page shows the
// channel as the viewport and the timeline call it (`rotate`) and the node
// by its name.

/** Internal attribute names (the transform node type's) and the channel each stands for. */
const kChannelNames: Record<string, string> = {
  rotateQuaternion: 'rotate',
  rotateOrder: 'rotate order',
  rotateMode: 'rotate mode',
  rotateAxis: 'rotate axis',
  rotatePivot: 'rotate pivot',
  rotatePivotTranslate: 'rotate pivot translate',
  scalePivot: 'scale pivot',
  scalePivotTranslate: 'scale pivot translate',
  offsetParentMatrix: 'offset parent matrix',
  parentMatrix: 'parent matrix',
  worldMatrix: 'world matrix',
};

const kChannelPattern = new RegExp(`\\b(${Object.keys(kChannelNames).join('|')})\\b`, 'g');
const kUuidPattern = /\b[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}\b/gi;

/** The user's name of an attribute (itself when it has no other). */
export function channelName(attr: string): string {
  return kChannelNames[attr] ?? attr;
}

/**
 * A message of the server in the user's words: internal attribute names
 * become channel names, node uuids the nodes' names (where `nodeName`
 * knows them).
 */
export function userText(text: string, nodeName: (uuid: string) => string | undefined = () => undefined): string {
  return text
    .replace(kChannelPattern, (attr: string) => kChannelNames[attr] ?? attr)
    .replace(kUuidPattern, (u: string) => nodeName(u.toLowerCase()) ?? nodeName(u) ?? u);
}
