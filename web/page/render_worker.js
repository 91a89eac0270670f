// The worker that holds svetlo's WebAssembly module (docs/web.md): a render blocks it, not
// the page, and its threads are the module's own workers. Messages in: {id, scene, isText,
// options}; out: {ready} once, then {id, width, height, seconds, pixels} or {id, error}.
importScripts('svetlo.js');

createSvetlo({
    // The module's files beside this script, whatever the page's own address.
    locateFile: (name) => new URL(name, self.location.href).href,
    // What the module's threads load (a modularized module inside a worker cannot tell).
    mainScriptUrlOrBlob: new URL('svetlo.js', self.location.href).href,
    print: (text) => console.log(text),
    printErr: (text) => console.warn(text),
}).then((module) => {
    module.FS.chdir('/scenes');
    const scenes = module.FS.readdir('/scenes').filter((name) => name.endsWith('.json')).sort();
    self.postMessage({ready: true, scenes, engines: JSON.parse(module.engines()),
                      cores: navigator.hardwareConcurrency || 1});
    self.onmessage = (event) => {
        const {id, scene, isText, options} = event.data;
        const out = module.render(scene, isText, JSON.stringify(options || {}));
        if (out.error !== undefined) {
            self.postMessage({id, error: out.error});
            return;
        }
        self.postMessage({id, width: out.width, height: out.height, seconds: out.seconds,
                          pixels: out.pixels}, [out.pixels.buffer]);
    };
}, (error) => self.postMessage({failed: String(error)}));
