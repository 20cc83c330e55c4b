  Inspector.prototype.setFrame = function (k) {
    var I = this;
    if (!I.frames || !isId(k, I.frameModels.length)) { return; }
    I.frame = k;
    I.models.yours = I.frameModels[k];
    if (I.slider && +I.slider.value !== k) { I.slider.value = String(k); }
    if (I.sel && I.sel.pane === 'yours') { I.select('yours', I.sel.kind, I.sel.id); }
    I.setFrameText();
    I.draw();
  };
  Inspector.prototype.setFrameText = function () {
    var I = this;
    if (!I.frames) { return; }
    var n = I.frameModels.length, fr = I.frames.list[I.frame] || {};
    I.frameText.textContent = 'frame ' + (I.frame + 1) + ' of ' + n + ': ' + (fr.label || '');
    var broken = I.frames.firstBroken === I.frame;
    I.frameBroken.textContent = broken ? 'first broken frame' : '';
    I.frameBroken.style.display = broken ? '' : 'none';
  };

